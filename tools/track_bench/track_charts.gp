# Charts of the tracker benchmark. gnuplot -e "outdir='docs/results/track'" track_charts.gp
set terminal pngcairo size 900,600 noenhanced
set datafile separator ","
set grid

set output outdir."/track_frontier.png"
set title "Tracked 640x480 sequence: time per frame against pose error (lower left is better)"
set xlabel "detection + corner refinement, ms per frame (median, one thread)"
set ylabel "median position error, mm"
set logscale xy
set key top right
plot outdir."/track_sequence.csv" every ::1 using 2:5:1 with labels point pt 7 offset char 1,0.6 title "2x2 board at 0.5 m", \
     outdir."/track_sequence.csv" every ::1 using 2:8:1 with labels point pt 5 offset char 1,-0.6 title "single 5 cm tag at 0.8 m"

unset logscale
set output outdir."/track_detection_rate.png"
set datafile separator whitespace
set title "Detection rate of a 5 cm tag36h11 (0-40 degrees, noise sigma 2)"
set xlabel "distance, m"
set ylabel "% detected"
set yrange [0:105]
set key bottom left
plot for [i=2:*] outdir."/track_detection_rate.dat" using 1:i with linespoints title columnheader(i)
