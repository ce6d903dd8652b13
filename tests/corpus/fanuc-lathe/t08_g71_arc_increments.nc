%
O0108 (G71 TYPE I OVER A FILLET, G01 IN-FEED, VALUES WITHOUT DECIMAL POINT)
(Start A: X50 Z1 = radius 25, Z 1. U3. R500: depth 3, retract 0.5 = 500 increments)
(Shape, radius/Z: A' 10/1, W-11000 = -11 mm to 10/-10,)
(G2 R10 to 20/-20: centre 20/-10 (Z-X plane, clockwise), 20/-35, U10 to 25/-35)
(No allowances. Levels 25 - 3k above 10: 22 19 16 13, 15/3 less 1 = 4)
(Level 22 meets the last element: Z -35)
(Levels 19 16 13 meet the fillet: Z = -10 - SQRT(100 - (level - 20)^2):)
(-10 - SQRT(99), -10 - SQRT(84), -10 - SQRT(51))
G18 G21 G40 G99
T0101
G97 S800 M3
G0 X50. Z1.
G71 U3. R500
G71 P30 Q40 F0.3
N30 G1 X20.
W-11000
G2 X40. W-10. R10.
G1 Z-35.
N40 U10.
G0 X80. Z30.
M30
%
