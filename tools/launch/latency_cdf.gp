# CDF of the per-stage latencies of a launcher run.
#   gnuplot -e "dir='build/demo'; out='docs/results/pipeline/latency_cdf.png'" tools/launch/latency_cdf.gp
set terminal pngcairo size 900,560 noenhanced
set output out
set datafile separator ","
set title "Latency per stage (CDF), ".dir
set xlabel "milliseconds"
set ylabel "fraction of frames"
set yrange [0:1.02]
set grid
set key bottom right
stats dir."/latency_samples.csv" every ::1 using 2 nooutput
plot for [stage in "capture_to_detection pose_to_world_state capture_to_overlay"] \
  dir."/latency_samples.csv" every ::1 using ((strcol(1) eq stage) ? $2 : 1/0):(1.0) smooth cnormal with lines lw 2 title stage
