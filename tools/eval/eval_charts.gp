# Charts of the evaluation's own studies. Called by tools/eval/write_evaluation.py with
#   gnuplot -e "dir='docs/results/eval'; thrown_ratio=3; left_behind_m=0.2" tools/eval/eval_charts.gp
# after it wrote the aggregated .dat files next to the CSVs.
set terminal pngcairo size 1200,480 font ',10'
set datafile separator ','

# 1. Tracking map: mean peak speed of the pushed bunny over the pusher's, per frame rate
#    and noise, for each way tracking drives the box. Column 7 is the cell's failure mark as
#    write_evaluation.py judged it: x thrown (above thrown_ratio), b left behind (pushed under
#    left_behind_m: the box passed through it) or ok.
set output dir.'/eval_tracking_map.png'
set multiplot layout 1,3 title sprintf("Bunny pushed by a tracked box: peak bunny speed / box speed (mean over seeds; failures: > %g thrown, marked x; pushed < %g m, left behind, marked b)", thrown_ratio, left_behind_m)
set xrange [-0.5:4.5]
set yrange [-0.5:3.5]
set xtics ('5' 0, '10' 1, '15' 2, '30' 3, '60' 4)
set ytics ('0' 0, '1 mm 0.2°' 1, '2 mm 0.4°' 2, '5 mm 1°' 3)
set xlabel 'tracking frame rate (Hz)'
set logscale cb
set cbrange [1:100]
set palette defined (0 '#2c7bb6', 1 '#ffffbf', 2 '#d7191c')
unset key
do for [drive in "screw screw+filter teleport"] {
  set title drive
  plot sprintf("< awk -F, '$3 == \"%s\"' '%s/eval_tracking_map.dat'", drive, dir) using 1:2:4 with image, \
       '' using 1:2:(sprintf('%.1f%s', $4, strcol(7) eq 'ok' ? '' : ' '.strcol(7))) with labels font ',9'
}
unset multiplot
unset logscale cb
set xrange [*:*]
set yrange [*:*]
set xtics auto
set ytics auto

# 2. Lost tracks and pose flips under 1 mm noise: peak bunny speed / box speed.
set terminal pngcairo size 1000,480 font ',10'
set output dir.'/eval_loss_flip.png'
set title "Tracking loss (re-acquired further on) and pose flips: peak bunny speed / box speed"
unset xlabel
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set logscale y
set yrange [1:200]
set ylabel 'peak speed ratio (log)'
set key top left
set xtics rotate by -20
plot dir.'/eval_loss_flip.dat' using 2:xtic(1) title 'screw', '' using 3 title 'screw+filter', '' using 4 title 'teleport'
unset logscale y
set yrange [*:*]
set xtics norotate
set style data points

# 3. Model size: cost against accuracy of the rest pose of a bunny set down upright
#    (reference: 70k bunny, box table, same friction).
set terminal pngcairo size 900,600 font ',10'
set output dir.'/eval_model_size.png'
set title "How much model the bunny scene needs: ms per step vs an upright bunny's rest-pose error against the 70k bunny"
set logscale xy
set xrange [0.1:60]
set xlabel 'ms per step (log)'
set ylabel 'upright rest position error (mm, log; 0 shown at 0.01)'
set key top right
at_least_001(x) = x > 0.01 ? x : 0.01
plot sprintf("< awk -F, 'NR > 1 && $3 == 1' '%s/eval_model_size.csv'", dir) using 4:(at_least_001($8)):(sprintf('%s, %s', stringcolumn(1), stringcolumn(10))) with labels point pt 7 ps 1.4 lc rgb '#0060c0' offset 1,0.5 left font ',8' title 'friction 0.5', \
     sprintf("< awk -F, 'NR > 1 && $3 == 0' '%s/eval_model_size.csv'", dir) using 4:(at_least_001($8)):(sprintf('%s, %s', stringcolumn(1), stringcolumn(10))) with labels point pt 5 ps 1.4 lc rgb '#cc4400' offset 1,-0.5 left font ',8' title 'frictionless'
unset logscale
set xrange [*:*]

# 4. End to end: capture-to-overlay latency against overlay registration error.
set output dir.'/eval_end_to_end.png'
set title "End to end (application 2, synthetic camera): latency vs where the tracked box is drawn"
set xlabel 'capture -> overlay latency, p50 (ms); bars to p95'
set ylabel 'overlay registration error of the box, p50 (px); bars to p95'
set key off
set xrange [0:*]
set yrange [0:*]
plot dir.'/eval_end_to_end.csv' every ::1 using 3:5:3:4:5:6 with xyerrorbars pt 7 ps 1.4 lc rgb '#0060c0', \
     '' every ::1 using 3:5:(stringcolumn(1).' / '.stringcolumn(2).($8 > 0 ? sprintf(', waits %g ms', $8) : '')) with labels offset 1,1 left font ',9'
set xrange [*:*]
set yrange [*:*]

# 5. Stacks over the time step: drift of the top box against cost, every engine.
set output dir.'/eval_stack_dt.png'
set title "Frictionless stack of 10 boxes: top-box drift vs ms per step over dt (red: toppled)"
set logscale xy
set xlabel 'ms per step (log)'
set ylabel 'largest top-box drift (mm, log)'
set key off
floor_mm(x) = x > 1e-3 ? x : 1e-3
plot sprintf("< awk -F, 'NR > 1 && $2 == 10' '%s/dyn_stack.csv'", dir) using 8:(floor_mm($6)):($4 > 0 ? 0xcc0000 : 0x0060c0) with points pt 7 ps 1.3 lc rgb variable, \
     '' using 8:(floor_mm($6)):(sprintf('%s %g ms', stringcolumn(1), $3 * 1000)) with labels offset 0.7,0 left font ',7'
