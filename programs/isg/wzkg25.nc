; Seed 002 (ISG kernel / TwinCAT CNC, TF5200 "Tool radius compensation (TRC)"),
; programming example 1: %WZKG25, contour for G25 (linear transition) with the
; selection modes G138 (path 1), G139 (path 2) and G05 (path 3). Exactly as printed
; below this header (T1 D1: D1 = radius 10 in config/tools.toml, as the seed's
; "tool radius of 10 mm"). Note: N340 has no G90, so it is still incremental (G91 from
; N315).
%WZKG25 (Contour for G25)
N10 G00 G90 T1 D1 X0 Y0 Z0 G17
(Presentation of contour) 
N15 G01 X20 Y20 F1000
N20 G91
N25 G1 X10
N30 X5 Y-5
N35 Y-5
N40 X-5 Y-3
N45 G01 G90 X0 Y0 F1000
(Path 1) 
N100 G138 G41 (Direct selection and TRC left of contour)
N105 G01 X20 Y20 F1000 (Compensation movement after G41)
N110 G25 (G25 linear transition)
N115 G1 G91 X10
N120 X5 Y-5
N125 Y-5
N130 X-5 Y-3
N135 G138 G40 (Direct deselection and TRC-off)
N140 G01 G90 X0 Y0 F1000 (Compensation movement after G40)
(Path 2) 
N200 G139 G41 (Indirect selection and TRC left of contour)
N205 G01 X20 Y20 F1000 (Compensation movement after G41)
N210 G25 (G25 linear transition)
N215 G1 G91 X10
N220 X5 Y-5
N225 Y-5
N230 X-5 Y-3
N235 G139 G40 (Indirect deselection and TRC-off)
N240 G01 G90 X0 Y0 F1000 (Compensation movement after G40)
(Path 3) 
N300 G05 G41 (Tangential selection and TRC left of contour)
N305 G01 X20 Y20 F1000 (Compensation movement after G41)
N310 G25 (G25 linear transition)
N315 G1 G91X10
N320X5 Y-5
N325 Y-5
N330 X-5 Y-3
N335 G05 G40 (Tangential deselection and TRC-off)
N340 G01 X20 Y20 F1000 (Compensation movement after G41)
N999 M30
