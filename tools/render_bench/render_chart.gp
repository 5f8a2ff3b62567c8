# gnuplot -e "outdir='docs/results/render'" render_chart.gp
set terminal pngcairo size 900,600 noenhanced
set output outdir."/render_bench.png"
set datafile separator ","
set title "640x480 overlay frame on OSMesa llvmpipe: draw + read-back + composite"
set xlabel "triangles drawn"
set ylabel "ms per frame (median)"
set logscale xy
set grid
set key top left
plot outdir."/render_bench.csv" every ::1 using 2:5 with points pt 7 title "total", \
     outdir."/render_bench.csv" every ::1 using 2:5:1 with labels offset char 0,1 notitle, \
     outdir."/render_bench.csv" every ::1 using 2:3 with points pt 6 title "draw + read-back"
