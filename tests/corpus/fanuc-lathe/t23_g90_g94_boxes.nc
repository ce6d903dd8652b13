%
O0123 (G90 OUTER DIAMETER CUTTING AND G94 END FACE CUTTING CYCLES)
(G90 from A = X52 Z2 = radius 26, Z 2: boxes to X46 = r23, X42 = r21, Z-30 kept)
(each: rapid to the cut's X at Z2, feed to Z-30, feed out to r26, rapid to Z2)
(The third: X40 R-2: the cut starts at radius 20 - 2 = 18 at Z2 and tapers to r20 at Z-30)
(G94 from A = X55 Z3 = radius 27.5, Z 3: faces to X20 = r10 at Z-1, Z-2)
(each: rapid to the cut's Z at r27.5, feed to r10, feed back to Z3, rapid to r27.5)
(The third: Z-3 R-1: the cut starts at Z-4 at r27.5 and runs to r10 at Z-3)
(End: X60 Z20 = radius 30, Z 20)
G18 G21 G40 G99
T0101
G96 S180 M3
G0 X52. Z2.
G90 X46. Z-30. F0.25
X42.
X40. R-2.
G0 X55. Z3.
G94 X20. Z-1. F0.2
Z-2.
Z-3. R-1.
G0 X60. Z20.
M30
%
