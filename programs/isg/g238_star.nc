; Beckhoff TF5200 programming manual, "Selecting inside corner of TRC (G238)": the star
; example (musterstern.nc), selection at the inner corner of the tip P2 (X0 Y100).
; Blocks N210..N999 as printed; the manual's V.G.WZR = 10 (tool radius 10) is written as D1
; (radius 10 in config/tools.toml), and the display pass N100..N200 is left out.
N2 G17 G00 X0 Y0 Z0 G90
N4 F10000
N210 G238 (Inside corner selection activated)
N220 D1 (Tool radius 10)
N230 G41 (Select TRC left of contour)
N240 G01 X0 Y100 (Approach block)
N310 X-20 Y20
N320 X-100 Y0
N330 X-20 Y-20
N340 X0 Y-100
N350 X20 Y-20
N360 X100 Y0
N370 X20 Y20
N380 G01 X0 Y100
N390 G40 (Deselect TRC)
N400 G00 X0 Y0
N999 M30
