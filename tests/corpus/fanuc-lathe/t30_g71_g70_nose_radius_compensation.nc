%
O0130 (G71 AND G70 WITH G42 IN THE SHAPE: ROUGHING THE COMPENSATED SHAPE, DIAMETERS)
(Start A: X44 Z2 = radius 22, Z 2. T0101: nose R0.8, edge position 3: tip = centre - 0.8/0.8)
(Shape, radius/Z: A' 10/2, 10/-10, face to 15/-10, G3 R5 about 15/-15 to 20/-15, 20/-25,)
(N20 G40 out to 24/-25. G42: the nose centre 0.8 outside: X 10.8 to the face's Z -9.2,)
(the face at Z -9.2 to X 15, the arc at R5.8 about 15/-15 to 20.8/-15, X 20.8 to Z -25)
(Tip path: A' 10/1.2, 10/-10, 14.2/-10, arc about 14.2/-15.8 to 20/-15.8, 20/-25.8,)
(then the G40 ramp to 24/-25. U0.4 W0.1 move it by 0.2/0.1:)
(A' 10.2/1.3, 10.2/-9.9, 14.4/-9.9, arc about 14.4/-15.7 R5.8 to 20.2/-15.7, 20.2/-25.7, 24.2/-24.9)
(Levels 22 - 2k above 10.2: 20 18 16 14 12, 11.8/2 rounded up less 1 = 5)
(Level 12 and 14 meet the face: Z -9.9)
(Levels 16 18 20 the arc: Z = -15.7 + SQRT(5.8^2 - (level - 14.4)^2):)
(-15.7 + SQRT(31.08), -15.7 + SQRT(20.68), -15.7 + SQRT(2.28))
(Retract 1 at 45 degrees, rapid back to Z 2. The run along the moved tip path,)
(back to A: X 22 first, then Z 2. G70: the shape as programmed with G42 ... G40;)
(preparation puts the tip on the path above without the allowances)
G18 G21 G40 G99
T0101
G96 S180 M3
G0 X44. Z2.
G71 U2. R1.
G71 P10 Q20 U0.4 W0.1 F0.25
N10 G0 G42 X20.
G1 Z-10. F0.1
X30.
G3 X40. Z-15. R5.
G1 Z-25.
N20 G40 X48.
G70 P10 Q20
G0 X80. Z50.
M30
%
