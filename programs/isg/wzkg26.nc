; Seed 002 (ISG kernel / TwinCAT CNC, TF5200 "Tool radius compensation (TRC)"),
; programming example 2: %WZKG26, contour for G26 (circular transition) with the
; selection modes G138 (path 4), G139 (path 5) and G05 (path 6). Exactly as printed
; below this header (T1 D1: D1 = radius 10 in config/tools.toml). Note: N640 has no G90,
; so it is still incremental (G91 from N615).
%WZKG26 (Contour for G26)
N10 G00 G90 T1 D1 X0 Y0 Z0 G17
(Presentation of contour) 
N15 G01 X20 Y20 F1000
N20 G91
N25 G1 X10
N30 X5 Y-5
N35 Y-5
N40 X-5 Y-3
N45 G01 G90 X0 Y0 F1000
(Path 4) 
N400 G138 G41 (Direct selection and TRC left of contour)
N405 G01 X20 Y20 F1000 (Compensation movement after G41)
N410 G26 (G26 circular transition)
N415 G1 G91 X10
N420 X5 Y-5
N425 Y-5
N430 X-5 Y-3
N435 G138 G40 (Direct deselection and TRC-off)
N440 G01 G90 X0 Y0 F1000 (Compensation movement after G40)
(Path 5) 
N500 G139 G41 (Indirect selection and TRC left of contour)
N505 G01 X20 Y20 F1000 (Compensation movement after G41)
N510 G26 (G26 circular transition)
N515 G1 G91 X10
N520 X5 Y-5
N525 Y-5
N530 X-5 Y-3
N535 G139 G40 (Indirect deselection and TRC-off)
N540 G01 G90 X0 Y0 F1000 (Compensation movement after G40)
(Path 6) 
N600 G05 G41 (Tangential selection and TRC left of contour)
N605 G01 X20 Y20 F1000 (Compensation movement after G41)
N610 G26 (G26 circular transition)
N615 G1 G91X10
N620 X5 Y-5
N625 Y-5
N630 X-5 Y-3
N635 G05 G40 (Tangential deselection and TRC-off)
N640 G01 X20 Y20 F1000 (Compensation movement after G41)
N999 M30
