%
O0121 (G92 THREADING CYCLE: M30 X 1.5 IN FIVE PASSES, A SPRING PASS WITH CHAMFER)
(Start A: X35 Z4 = radius 17.5, Z 4. Each pass: rapid in X at Z4, thread to Z-25,)
(rapid out to radius 17.5, rapid back to Z4. The next blocks give X only: Z kept)
(Passes at radius 14.65 14.45 14.25 14.1 14.025 = X29.3 28.9 28.5 28.2 28.05)
(G76 P011060 sets the chamfer to 1.0 lead = 1.5 at 45 degrees: the spring pass)
(threads to Z-25 + 1.5 = -23.5 at radius 14.025, then out to 14.025 + 1.5 = 15.525 at Z-25)
(End: X60 Z20 = radius 30, Z 20)
G18 G21 G40 G99
T0101
G97 S500 M3
G0 X35. Z4.
G92 X29.3 Z-25. F1.5
X28.9
X28.5
X28.2
X28.05
G76 P011060
G92 X28.05 Z-25. F1.5
G0 X60. Z20.
M30
%
