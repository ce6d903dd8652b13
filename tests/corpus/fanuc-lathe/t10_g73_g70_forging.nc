%
O0110 (G73 PATTERN REPEATING OF A FORGED BLANK AND G70, DIAMETERS)
(Start A: X60 Z3 = radius 30, Z 3. Shape N10...N20, radius/Z:)
(A' 8/1 at rapid, 8/-8, G2 R8 to 16/-16 about 16/-8, 16/-24,)
(down to 13/-30, out to B = 30/-30: not monotonic, G73 takes it)
(G73 U3 W1.5 R3: escape 3 on the radius and 1.5 in Z, three passes)
(U0.4 W0.1: allowances 0.2 on the radius and 0.1 in Z)
(Shifts: first 3.2/1.6, last 0.2/0.1, between 1.7/0.85)
(Each pass: the whole shape moved by its shift, arc centre with it,)
(at F0.25, then home at rapid, X first: radius 30, then Z 3)
(G70: the shape as written at F0.1, then home X first)
G18 G21 G40 G99
T0101
G96 S150 M3
G0 X60. Z3.
G73 U3. W1.5 R3
G73 P10 Q20 U0.4 W0.1 F0.25
N10 G0 X16. Z1.
G1 Z-8. F0.1
G2 X32. Z-16. R8.
G1 Z-24.
X26. Z-30.
N20 X60.
G70 P10 Q20
G0 X100. Z50.
M30
%
