; ISG feed adaption (G10/G11, TF5200 "Adapting feed of TRC"): with G11 the programmed feed acts
; at the contour. D2 = radius 5 (config/tools.toml); G26 circular transitions.
; N90 runs back over the end of N50's arc (the contour touches itself): the shipped deep check
; refuses it with alarm 3021; it runs with the ISG control's own checking:
; --md trc.bottleneck_window=0 --md trc.whole_program_check=false.
N10 G17 G90 G00 X-20 Y20 D2
N20 G26 G11
N30 G41 G01 X0 Y20 F600
N40 X20 Y20
N50 G03 X40 Y20 I10 J0
N60 G01 X40 Y40
N70 G02 X60 Y40 I10 J0
N80 G01 X60 Y20
N90 X30 Y20
N100 G40 X30 Y0
N110 M30
