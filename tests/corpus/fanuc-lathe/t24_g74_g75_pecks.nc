%
O0124 (G75 GROOVING IN THREE COLUMNS AND G74 PECK DRILLING ON THE CENTRE)
(G75 from A = X42 Z-15 = radius 21, Z -15; return e 0.5. Grooves to X30 = r15,)
(pecks of 3 on the radius P3000: feed to r18, back 0.5 to r18.5, feed to r15)
(out to r21, rapid on by 2 in Z Q2000: columns at Z -15, -17, -19, then back to A)
(G74 from A = X0 Z2; return e 1. Hole to Z-12 in pecks of 5 Q5000: feed to Z-3,)
(back to Z-2, feed to Z-8, back to Z-7, feed to Z-12, rapid out to Z2 = A)
(End: X60 Z20 = radius 30, Z 20)
G18 G21 G40 G99
T0101
G97 S400 M3
G0 X42. Z-15.
G75 R0.5
G75 X30. Z-19. P3000 Q2000 F0.08
G0 X0. Z2.
G74 R1.
G74 Z-12. Q5000 F0.1
G0 X60. Z20.
M30
%
