%
O0112 (G70 WITH THE NOSE RADIUS COMPENSATION WRITTEN IN ITS SHAPE, DIAMETERS)
(Start A: X44 Z2 = radius 22, Z 2. T0101: nose 0.8, edge position 3)
(N10 G42: the compensation starts with the move to A' 8/2)
(8/-10, taper to 12/-18, 12/-30; N20 G40 ends it on the way out)
(to 22/-30. Return to A: X is there, Z 2 alone; then X80 Z50 = 40/50)
G18 G21 G40 G99
T0101
G96 S180 M3
G0 X44. Z2.
G70 P10 Q20
G0 X80. Z50.
M30
N10 G0 G42 X16. Z2.
G1 Z-10. F0.1
X24. Z-18.
Z-30.
N20 G40 X44.
%
