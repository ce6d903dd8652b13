%
O0122 (G76 MULTIPLE THREADING CYCLE: OUTSIDE THREAD, FLANK INFEED 60 DEGREES)
(Start A: X28 Z5 = radius 14, Z 5. Root at the end X21.6 Z-20 = radius 10.8)
(k = 1.2 P1200, first depth 0.3 Q300, minimum 0.1 Q100, allowance 0.05, m = 2)
(Depths: 0.3, then + 0.3 * [sqrt 2 - 1] = 0.424264; the next steps 0.3 * [sqrt n)
(- sqrt n-1] are under 0.1: + 0.1 each: 0.524264 0.624264 0.724264 0.824264)
(0.924264 1.024264 1.124264, then 1.224264 passes k - d = 1.15: 1.15)
(Then two finishing passes at 1.2. Pass at depth D: X = 10.8 + 1.2 - D)
(shifted back along +Z by [1.2 - D] * tan 30 = [1.2 - D] * 0.577350269)
(Each pass: rapid to X at Z 5 + shift, thread to X at Z -20 + shift, rapid out to)
(radius 14, rapid back to Z5. End: X60 Z20 = radius 30, Z 20)
G18 G21 G40 G99
T0101
G97 S500 M3
G0 X28. Z5.
G76 P020060 Q100 R0.05
G76 X21.6 Z-20. P1200 Q300 F2.
G0 X60. Z20.
M30
%
