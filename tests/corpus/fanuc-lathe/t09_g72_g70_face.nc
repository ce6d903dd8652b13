%
O0109 (G72 STOCK REMOVAL IN FACING AND G70 FINISHING, DIAMETERS)
(Start A: X44 Z2 = radius 22, Z 2. Shape N10...N20, radius/Z:)
(A' 22/-6 at rapid, 20/-6, G3 R6 to 14/0 about 20/0, 5/0, B = 0/1)
(G72 W2 R0.5: depth 2 along Z, retract 0.5 at 45 degrees)
(U0.4 W0.2: the shape moves +0.2 in X radius and +0.2 in Z:)
(A' 22.2/-5.8, 20.2/-5.8, arc to 14.2/0.2 about 20.2/0.2, 5.2/0.2, 0.2/1.2)
(Levels in Z 2 - 2k while above -5.8: 0 -2 -4, 7.8/2 rounded up less 1 = 3)
(Each level meets the arc: X = 20.2 - SQRT(36 - (level - 0.2)^2):)
(Z0: 14.2033, Z-2: 14.6179, Z-4: 15.9152. Passes in along Z at X44,)
(across at F0.2, out by 0.5 in X and Z, back to X44. Then the moved)
(shape, home Z first, then X. G70: the shape as written, home X first)
G18 G21 G40 G99
T0101
G96 S150 M3
G0 X44. Z2.
G72 W2. R0.5
G72 P10 Q20 U0.4 W0.2 F0.2
N10 G0 Z-6.
G1 X40. F0.1
G3 X28. Z0. R6.
G1 X10.
N20 X0. Z1.
G70 P10 Q20
G0 X100. Z50.
M30
%
