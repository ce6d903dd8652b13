; Seed 002 (ISG kernel / TwinCAT CNC), "Change of tool data", programming example
; N30..N170 (D100 = radius 10, D2 = radius 5 in config/tools.toml).
; Added: the program header %D_CHANGE, N10 with G90 and the feed F1000 (the printed
; fragment programs G1 in N50 without any feed), and N999 M30.
; Changed: N140. As printed, "N140 G02 X10 Y10 I-15" starts at X20 Y20 (end of N130), so
; its centre is X5 Y20 and the end point X10 Y10 lies sqrt(5^2+10^2) = 11.18 mm from it,
; not 15 mm: the printed block is rejected (circle end point error). Keeping N130 (the
; compensatory movement of TRC to X20 Y20) and the "full circle with radius 15" of N90,
; N140 here ends where it starts: G02 X20 Y20 I-15 (full circle about X5 Y20).
; Its two circles (N90 with D100, N140 with D2) and the move between them overlap at one
; depth: the shipped deep check (trc.bottleneck_window = 64, the whole-program check) refuses
; it with alarm 3021 (N90 comes within reach of N130). It runs with the ISG control's own
; checking: --md trc.bottleneck_window=0 --md trc.whole_program_check=false.
%D_CHANGE
N10 G90 F1000 (added: absolute dimensions, feed)
N30 G0 D0 X0 Y0 Z0 G17 (X-Y-Plane)
N40 G0 D100 X10 Y10 (Selection of TLC)
N50 G1 Z0
N60 G0 Z100
N70 G41 (Selection of TRC with data block D100)
N80 G1 Z0
N90 G2 X10 Y10 I-15 (Full circle with radius 15)
N100 G0 Z100
N110 D2 Z200 (Other compensation data block, i.e.)
(other values for TLC and TRC)
N120 G1 Z0 (Here compensatory movement of TLC occurs)
N130 G1 X20 Y20 (Compensatory movement of TRC)
N140 G02 X20 Y20 I-15 (The TRC is now executed with the data block; changed, see header)
N150 G0 Z100
N160 G40 (Deselection of TRC)
N170 X0
N999 M30
