%
O0131 (G72 AND G70 WITH G41 IN THE SHAPE: FACING THE COMPENSATED SHAPE, DIAMETERS)
(Start A: X84 Z2 = radius 42, Z 2. T0101: nose R0.8, edge position 3: tip = centre - 0.8/0.8)
(Shape, radius/Z: A' 42/-6, the face along -X to 30/-6, taper to 20/-2, face to 10/-2,)
(N20 G40 out to 10/2. G41: the nose on the +Z side of travel along -X)
(Nose centre: the face at Z -5.2; the taper X = 30 - 2.5(Z + 6) moved out by)
(0.8 SQRT(1 + 2.5^2) = 2.154066 in X: X = 32.154066 - 2.5(Z + 6); they meet at)
(30.154066/-5.2; an arc about the edge 20/-2 to 20/-1.2; the face at Z -1.2 to X 10)
(Tip path: A' 41.2/-6, 29.354066/-6, the taper X = 31.354066 - 2.5(Z + 6.8) to)
(19.497113/-2.057219, the arc about 19.2/-2.8 to 19.2/-2, 9.2/-2, the G40 ramp to 10/2)
(G72 W1.5 R0.5: levels 2 - 1.5k above -6: 0.5 -1 -2.5 -4 -5.5, 8/1.5 rounded up less 1 = 5)
(0.5 and -1 meet the ramp: X = 9.2 + 0.8(Z + 2)/4 = 9.7, 9.4)
(-2.5 -4 -5.5 meet the taper: X = 31.354066 - 2.5(Z + 6.8) = 20.604066, 24.354066, 28.104066)
(Retract 0.5 at 45 degrees: Z and X up, rapid back to X 42. The run along the tip path,)
(back to A: Z 2 first, then X. G70: the shape as programmed with G41 ... G40)
G18 G21 G40 G99
T0101
G96 S180 M3
G0 X84. Z2.
G72 W1.5 R0.5
G72 P10 Q20 F0.25
N10 G0 G41 Z-6.
G1 X60. F0.1
X40. Z-2.
X20.
N20 G40 Z2.
G70 P10 Q20
G0 X100. Z50.
M30
%
