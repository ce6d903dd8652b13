; Seed 002 (ISG kernel / TwinCAT CNC), "Dynamic change of tool radius": grinding cycle
; N00..N999 exactly as printed below this header. D6 = radius 10 in config/tools.toml;
; the $FOR loop runs for V.P.LAUF = 0, 10, ..., 100 (11 passes, end value inclusive) and
; reduces the active tool radius V.G.WZ_AKT.R by V.P.VERSCHLEISS = 0.010 per pass.
N00 G1 G90 X0 D6 F5 
N10 G41 G26 (Selection of TRC) 
N20 X0 Y250 (Starting point) 
N30 V.P.VERSCHLEISS = 0.010 
N100 $FOR V.P.LAUF = 0,100,10 (Grinding cycle) 
N110 X300 
N120 Y200 
N130 X0 
N140 Y250 (Tool radius is always getting smaller)
N150 V.G.WZ_AKT.R = V.G.WZ_AKT.R - V.P.VERSCHLEISS 
N160 $ENDFOR 
N200 G40 X300 (De-selection of TRC) 
N999 M30
