%
O0107 (G71 TYPE I ROUGHING AND G70 FINISHING OF A SHAFT, DIAMETERS)
(Start A: X40 Z2 = radius 20, Z 2. Shape N10...N20, radius:)
(A' 10/2, then 10/-10, taper to 15/-20, 15/-30, out to 20/-30 = B)
(G71 U2 R1: depth 2 on the radius, retract 1 at 45 degrees)
(U0.4 W0.2: the shape moves +0.2 in X radius and +0.2 in Z:)
(A' 10.2/2.2, 10.2/-9.8, 15.2/-19.8, 15.2/-29.8, 20.2/-29.8)
(Levels 20 - 2k while above 10.2: 18 16 14 12, 9.8/2 rounded up less 1 = 4)
(Level 18 and 16 meet the shape on its last element: Z -29.8)
(Level 14 on the taper: Z = -9.8 + (14 - 10.2) * -10/5 = -17.4)
(Level 12: Z = -9.8 + (12 - 10.2) * -2 = -13.4)
G18 G21 G40 G99
T0101
G96 S180 M3
G0 X40. Z2.
G71 U2. R1.
G71 P10 Q20 U0.4 W0.2 F0.25
N10 G0 X20. S220
G1 Z-10. F0.1
X30. Z-20.
Z-30.
N20 X40.
G70 P10 Q20
G0 X60. Z20.
M30
%
