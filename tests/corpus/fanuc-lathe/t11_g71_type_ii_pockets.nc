%
O0111 (G71 TYPE II: TWO POCKETS, ALLOWANCE IN X ONLY, DIAMETERS)
(Start A: X40 Z2 = radius 20, Z 2. N10 has X and Z: type II. Radius/Z:)
(A' 10/2, 10/-4, down to 4/-8, 4/-12, up to 12/-16, 12/-18, down to)
(6/-22, 6/-26, up to 16/-30, B = 20/-30. U0.4: all X + 0.2)
(G71 U3 R0.5. Deepest 20 - 4.2 = 15.8: levels X 17 14 11 8 5)
(17: one stretch Z 2 to -30 (B); 14: Z 2 to -29.12 on the last rise)
(11: Z 2 to -15.4 (first rise) and -18.8 to -27.92 (second pocket))
(8: -5.4667 to -13.9 and -20.8 to -26.72; 5: -7.4667 to -12.4)
(Between stretches: up to the deepest level cut over the way less 0.5:)
(X 14.5 here, along Z, down at rapid to the level above, in)
(by 3 at F0.2, along, out by 0.5 at 45 degrees. Back to A over X 11.5,)
(then the moved shape from A, home X first. G70: the shape as written)
G18 G21 G40 G99
T0101
G96 S150 M3
G0 X40. Z2.
G71 U3. R0.5
G71 P10 Q20 U0.4 F0.2
N10 G0 X20. Z2.
G1 Z-4. F0.1
X8. Z-8.
Z-12.
X24. Z-16.
Z-18.
X12. Z-22.
Z-26.
X32. Z-30.
N20 X40.
G70 P10 Q20
G0 X80. Z50.
M30
%
