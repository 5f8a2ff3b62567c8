# Charts of the CCD benchmark (called by run_benchmarks.sh with summary, tunnelling, outdir).
set datafile separator ','
set terminal pngcairo size 900,600 font ',11'

# 1. Speed against accuracy: median time per query against the largest TOI error.
#    Red: methods that missed collisions; labels say when TOIs came out late.
set output outdir.'/ccd_speed_accuracy.png'
set title "CCD speed vs accuracy (bunny 5k vs bunny 5k, random screw motions)"
set logscale xy
set xlabel 'median time per query (us, log)'
set ylabel 'largest |TOI error| over the hits (fraction of the step, log)'
set format y '10^{%T}'
set grid
set key off
clamp_low(x) = (x > 1e-10 ? x : 1e-10)
plot summary every ::1 using 12:(clamp_low($10)):($5 > 0 ? 0xcc0000 : 0x0060c0) with points pt 7 ps 1.6 lc rgb variable, \
     summary every ::1 using 12:(clamp_low($10) * (int($0) % 2 ? 0.45 : 2.2)): \
       (stringcolumn(1).($6 > 0 ? sprintf(', %d late', $6) : '').($5 > 0 ? sprintf(', %d missed', $5) : '')) \
       with labels offset 0.8,0 left font ',9'

# 2. Tunnelling: missed-collision rate against travel per step over thickness.
set output outdir.'/ccd_tunnelling.png'
set title "Missed collisions: a 1 cm cube flying through a 1 cm plate"
unset logscale y
set logscale x
set format y '%.1f'
set xlabel 'travel per step / (plate thickness + cube side)  (log)'
set ylabel 'missed-collision rate'
set yrange [-0.05:1.05]
set key outside right
set label 1 "arphys-ccd, discrete-1000 and fcl-ca-obbrss: no misses" at graph 0.03, graph 0.93 font ',10'
methods = "discrete-10 discrete-100 discrete-1000 fcl-naive-10 fcl-naive-100 fcl-ca-obbrss arphys-ccd"
rows(m) = sprintf("< awk -F, '$2 == \"%s\"' '%s'", m, tunnelling)
plot for [m in methods] rows(m) using 1:3 with linespoints lw (m eq 'arphys-ccd' ? 3 : 2) \
       ps (m eq 'arphys-ccd' ? 1.8 : 1) title m
