# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0237143 0.0161133 0.00868627 "0.3" "0.3"
0.0180196 0.0633659 0.0348156 "1" "1"
EOD
# WCC auto
$group1 << EOD
0.0105632 0.000313261 0.00015512 "1" "1"
0.00535427 0.000501095 0.000205999 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0256111 0.00073673 0.000322758 "1" "1"
0.00543614 0.000501095 0.000205999 "inf" "inf"
EOD
# cholmod
$group3 << EOD
0.0770485 2.05832e-14 5.22572e-16 "" ""
EOD
# umfpack
$group4 << EOD
0.149719 2.05832e-14 8.04567e-16 "" ""
EOD
# eigen
$group5 << EOD
0.298025 9.67925e-14 3.16255e-14 "" ""
EOD
# eigen_cholmod
$group6 << EOD
0.0799815 2.05832e-14 5.22572e-16 "" ""
EOD
# trilinos_amg_cg
$group7 << EOD
0.0323776 3.41841e-07 9.26909e-08 "1e-06" "1e-06"
0.019469 0.000540196 0.000241212 "0.001" "0.001"
EOD
# warp_preconditioned_cg
$group8 << EOD
0.0186911 2.9894e-07 9.3692e-08 "1e-06" "1e-06"
0.00785608 0.000501095 0.000205999 "0.001" "0.001"
EOD
# WCC target error
$group9 << EOD
0.0356144 0.00542029 0.00352566 "1%" "1%"
EOD
$front_max << EOD
0.00535427 0.000501095
0.00785608 0.000501095
0.0105632 0.000313261
0.0186911 2.9894e-07
EOD
$front_rms << EOD
0.00535427 0.000205999
0.00785608 0.000205999
0.0105632 0.00015512
0.0186911 9.3692e-08
0.0323776 9.26909e-08
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1788,650 font ",11"
} else {
  set terminal png size 1788,650
}
set termoption noenhanced
set output "doc/backends/torus_pull_fine.png"
set multiplot layout 1,2 margins 0.05034, 0.8389, 0.1077, 0.9154 spacing 0.06152 title "torus_pull_fine: 10035 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8473, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set logscale x
set xrange [0.00374799:0.417235]
set arrow 1 from 0.0407322, graph 0 to 0.0407322, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0407322, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "cholmod", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:2 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "umfpack", \
     $group4 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:2 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "eigen", \
     $group5 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle, \
     $group6 using 1:2 with points pointtype 4 pointsize 1.6 linecolor rgb "#e51e10" title "eigen_cholmod", \
     $group6 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#e51e10" notitle, \
     $group7 using 1:2 with points pointtype 6 pointsize 1.6 linecolor rgb "#000000" title "trilinos_amg_cg", \
     $group7 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#000000" notitle, \
     $group8 using 1:2 with points pointtype 8 pointsize 1.6 linecolor rgb "#a0522d" title "warp_preconditioned_cg", \
     $group8 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#a0522d" notitle, \
     $group9 using 1:2 with points pointtype 10 pointsize 1.6 linecolor rgb "#ff69b4" title "WCC target error", \
     $group9 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#ff69b4" notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "cholmod", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:3 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "umfpack", \
     $group4 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:3 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "eigen", \
     $group5 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle, \
     $group6 using 1:3 with points pointtype 4 pointsize 1.6 linecolor rgb "#e51e10" title "eigen_cholmod", \
     $group6 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#e51e10" notitle, \
     $group7 using 1:3 with points pointtype 6 pointsize 1.6 linecolor rgb "#000000" title "trilinos_amg_cg", \
     $group7 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#000000" notitle, \
     $group8 using 1:3 with points pointtype 8 pointsize 1.6 linecolor rgb "#a0522d" title "warp_preconditioned_cg", \
     $group8 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#a0522d" notitle, \
     $group9 using 1:3 with points pointtype 10 pointsize 1.6 linecolor rgb "#ff69b4" title "WCC target error", \
     $group9 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#ff69b4" notitle
unset multiplot
