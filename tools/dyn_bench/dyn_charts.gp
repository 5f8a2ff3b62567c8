# Charts of the dynamics benchmark (called by run_benchmarks.sh with drop and outdir).
set datafile separator ','
set terminal pngcairo size 900,600 font ',11'
engines = "arphys arphys-10um arphys-iterative bullet ode-step ode-quick mujoco-newton mujoco-pgs mujoco-cg"
rows(e, mu) = sprintf("< awk -F, '$1 == \"%s\" && $3 == %s' '%s'", e, mu, drop)

# 1. Time per step against the number of boxes (frictionless and with friction 0.5).
set output outdir.'/dyn_drop_timing.png'
set multiplot layout 1,2 title "N boxes dropped on a plane, dt = 1 ms: median time per step"
set logscale xy
set xlabel 'boxes'
set ylabel 'ms per step (log)'
set grid
set key top left font ',8'
set title 'frictionless'
plot for [e in engines] rows(e, "0") using 2:4 with linespoints lw 2 title e
set title 'friction 0.5'
plot for [e in engines] rows(e, "0.5") using 2:4 with linespoints lw 2 title e
unset multiplot

# 2. Accuracy against speed: the deepest penetration (a box corner into the plane, or
#    one box into another) against time per step, all N and frictions (0: drawn at the
#    1e-4 mm floor).
set output outdir.'/dyn_accuracy_speed.png'
set title "Penetration against speed (drop scenes, all N, with and without friction)"
set xlabel 'median ms per step (log)'
set ylabel 'deepest penetration, mm (log; 0 drawn at 1e-4)'
set key outside right
floor_mm(x) = (x > 1e-4 ? x : 1e-4)
plot for [e in engines] sprintf("< awk -F, '$1 == \"%s\"' '%s'", e, drop) using 4:(floor_mm($5 > $8 ? $5 : $8)) with points pt 7 ps 1.4 title e

# 3. The pile as the anchor measured the issue's target (2 s, mean ms per step): the
#    deeper of box-into-plane and box-into-box against time per step (only when the
#    anchor-pile scene ran).
if (exists("anchor")) {
  set output outdir.'/dyn_anchor_pile.png'
  set title "1000 boxes, dt = 1 ms, 2 s: penetration against mean time per step"
  set xlabel 'mean ms per step = wall s per simulated s (log)'
  set ylabel 'deepest penetration, mm (log)'
  set key outside right
  plot for [e in "arphys arphys-10um bullet ode-quick"] for [mu in "0 0.5"] \
    sprintf("< awk -F, '$1 == \"%s\" && $2 == %s' '%s'", e, mu, anchor) \
    using 3:(floor_mm($5 > $6 ? $5 : $6)) with points pt (mu eq "0" ? 7 : 5) ps 1.6 title sprintf("%s, mu %s", e, mu)
}

# 4. The paper's bunny scenes on every engine (only when the bunnies-peers scene ran):
#    the deepest overlap of any two bodies against ms per step (0: drawn at 1e-4 mm).
if (exists("bunnies")) {
  set output outdir.'/dyn_bunnies_peers.png'
  set title "bunnies20 (circles) and bunnies100 (squares), dt = 10 ms, 3 s: overlap against time per step"
  set xlabel 'ms per step (log)'
  set ylabel 'deepest overlap, mm (log; 0 drawn at 1e-4)'
  set key outside right
  plot for [e in "arphys bullet-compound bullet-gimpact mujoco ode-trimesh"] for [s in "bunnies20 bunnies100"] \
    sprintf("< awk -F, '$2 == \"%s\" && $1 == \"%s\"' '%s'", e, s, bunnies) \
    using 3:(floor_mm($5)) with points pt (s eq "bunnies20" ? 7 : 5) ps 1.6 lc (e eq "arphys" ? 1 : e eq "bullet-compound" ? 2 : e eq "bullet-gimpact" ? 3 : e eq "mujoco" ? 4 : 6) \
    title sprintf("%s, %s", e, s)
}
