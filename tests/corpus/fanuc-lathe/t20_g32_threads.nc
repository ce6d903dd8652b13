%
O0120 (G32 THREAD CUTTING: STRAIGHT PASSES AND A TAPER, WRITTEN OUT)
(Start X24 Z5 = radius 12, Z 5. Lead F2 along Z: 2 mm per revolution)
(Pass 1: in to X19.2 = radius 9.6, G32 to Z-30, out to radius 12, back to Z5)
(Pass 2: X18.6 = radius 9.3, the same box)
(Taper: X17.8 Z5 to X19.8 Z-30 = radius 8.9 to 9.9, 1 in X over 35 in Z:)
(Z is the longer axis, the path feed 2 * sqrt 1226 / 35 = 2.000816)
(End: X60 Z20 = radius 30, Z 20)
G18 G21 G40 G99
T0101
G97 S600 M3
G0 X24. Z5.
X19.2
G32 Z-30. F2.
G0 X24.
Z5.
X18.6
G32 Z-30.
G0 X24.
Z5.
X17.8
G32 X19.8 Z-30.
G0 X24.
Z5.
G0 X60. Z20.
M30
%
