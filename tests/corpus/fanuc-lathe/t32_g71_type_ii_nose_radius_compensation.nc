%
O0132 (G71 TYPE II AND G70 WITH G42 IN THE SHAPE: POCKETS ROUGHED ON THE NOSE PATH, DIAMETERS)
(Start A: X34 Z2 = radius 17, Z 2. T0101: nose R0.8, edge position 3: tip = centre - 0.8/0.8)
(Shape, radius/Z: N10 G42 to A' 12/2, 12/-5, a 45 degree flank down to 6/-11, 6/-15,)
(a 45 degree flank up to 12/-21, 12/-25, N20 G40 out to 20/-25. q = 0.8/SQRT(2) = 0.565685)
(Nose centre 0.8 above: X 12.8 to Z -5; an arc R0.8 about the convex edge 12/-5 to)
(12.565685/-5.565685; the flank's parallel X - Z = 17 + 0.8 SQRT(2) meets X 6.8 at)
(Z -10.2 - 0.8 SQRT(2) = -11.331371; the rising flank's X + Z = -9 + 0.8 SQRT(2) meets)
(it at Z -14.668629; up to 12.565685/-20.434315, an arc about the edge 12/-21 to 12.8/-21)
(Tip path moved by U0.4 (0.2 on the radius): A' 12.2/1.2, 12.2/-5.8, the arc about)
(11.4/-5.8 to 11.965685/-6.365685, 6.2/-12.131371, 6.2/-15.468629, 11.965685/-21.234315,)
(the arc about 11.4/-21.8 to 12.2/-21.8, 12.2/-25.8, the G40 ramp to 20.2/-25)
(Its flanks: X - Z = 18.331371 falling, X + Z = -9.268629 rising)
(G71 U2 R0.5: deepest 17 - 6.2 = 10.8: levels X 15 13 11 9 7, 10.8/2 rounded up less 1 = 5)
(15: from N10's move at Z 2 - 0.8 x 2/4.8 = 1.666667, in at rapid, to the ramp at)
(Z -25.8 + 0.8 x 2.8/8 = -25.52, out 0.5 at 45 degrees to 15.5/-25.02)
(13: from Z 2 - 0.8 x 4/4.8 = 1.333333 to -25.72 on the ramp, out to 13.5/-25.22)
(11 9 7: from the falling flank Z = L - 18.331371 to the rising one Z = -9.268629 - L:)
(-7.331371 to -20.268629, -9.331371 to -18.268629, -11.331371 to -16.268629)
(The way to a stretch: up to the deepest level cut over the whole way less 0.5, along Z,)
(down at rapid to the level above, in at F0.2. The ramp turns back in Z to -25 and rises)
(to X 20.2, above A: to levels 13 and 11 from behind its end, up to X 17 first.)
(To 9 and 7 the rising flank is the shallowest, at X 10.5 and 8.5: levels 11 and 9 cut,)
(across at X 11.5 and 9.5 where the retract is)
(Back to A over X 17, the moved tip path from A, home X first: 17/-25, 17/2)
(G70: the shape as programmed with G42 ... G40, home X first. Preparation puts the tip)
(on the tip path above without the allowance)
G18 G21 G40 G99
T0101
G96 S150 M3
G0 X34. Z2.
G71 U2. R0.5
G71 P10 Q20 U0.4 F0.2
N10 G0 G42 X24. Z2.
G1 Z-5. F0.1
X12. Z-11.
Z-15.
X24. Z-21.
Z-25.
N20 G40 X40.
G70 P10 Q20
G0 X80. Z50.
M30
%
