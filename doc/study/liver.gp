# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.000430982 0.00542781 0.00244898 "0.03" "0.03"
0.000326516 0.0151035 0.00677565 "0.1" "0.1"
0.00027086 0.0261565 0.0117701 "0.3" "0.3"
0.000318225 0.0406232 0.0183263 "1" "1"
0.000230014 0.0505519 0.0229148 "3" "3"
0.00012606 0.119057 0.0606778 "inf" "inf"
EOD
# WCC delayed_top
$group1 << EOD
0.000420356 0.000116003 2.1682e-05 "0.3" "0.3"
0.000398245 5.21885e-05 2.66912e-05 "1" "1"
0.000398767 8.59023e-05 1.88908e-05 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.000411752 0.000118866 2.24838e-05 "0.3" "0.3"
0.000387677 4.93769e-05 2.50142e-05 "1" "1"
0.000388978 8.59023e-05 1.88908e-05 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.000387761 0.000118866 2.49582e-05 "0.3" "0.3"
0.000448127 8.13155e-05 2.54444e-05 "1" "1"
0.000372232 8.59023e-05 1.88908e-05 "inf" "inf"
EOD
$front_max << EOD
0.00012606 0.119057
0.000230014 0.0505519
0.00027086 0.0261565
0.000326516 0.0151035
0.000372232 8.59023e-05
0.000387677 4.93769e-05
EOD
$front_rms << EOD
0.00012606 0.0606778
0.000230014 0.0229148
0.00027086 0.0117701
0.000326516 0.00677565
0.000372232 1.88908e-05
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1500,650 font ",11"
} else {
  set terminal png size 1500,650
}
set termoption noenhanced
set output "doc/study/liver.png"
set multiplot layout 1,2 title "liver: 534 unknowns, 200 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key below horizontal
set bmargin 6
set xlabel "seconds per step"
set xrange [0:0.00126396]
set arrow 1 from 0.00117033, graph 0 to 0.00117033, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.00117033, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor 1 title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor lt 1 notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor 2 title "WCC delayed_top", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor lt 2 notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor 3 title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor lt 3 notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor 4 title "WCC auto", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor lt 4 notitle
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor 1 title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor lt 1 notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor 2 title "WCC delayed_top", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor lt 2 notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor 3 title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor lt 3 notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor 4 title "WCC auto", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor lt 4 notitle
unset multiplot
