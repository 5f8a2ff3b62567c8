#!/usr/bin/env python3
"""Summarises tools/view/view_cost.sh's runs: the view's CPU and each stage with and without it.

    view_cost.py RAW_DIR OUT_DIR   (RAW_DIR holds without-K/ and with-K/ launcher outputs)

Writes OUT_DIR/view_cost.csv (stage, p50 and p99 without and with the view, medians over the
pairs, and their ratios) and prints a table."""
import json
import re
import statistics
import sys
from pathlib import Path


def stages(run: Path) -> dict:
    return json.loads((run / "latency.json").read_text())["stages"]


def view_cpu_percent(run: Path) -> float:
    """The view's CPU over its life, from its last log line ("cpu X s over Y s")."""
    match = re.search(r"cpu ([0-9.]+) s over ([0-9.]+) s", (run / "view.log").read_text())
    if not match:
        sys.exit(f"view_cost.py: no cpu line in {run / 'view.log'}")
    return 100 * float(match.group(1)) / float(match.group(2))


def main() -> None:
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    raw, out = Path(sys.argv[1]), Path(sys.argv[2])
    without = sorted(raw.glob("without-*"))
    with_view = sorted(raw.glob("with-*"))
    if not without or len(without) != len(with_view):
        sys.exit(f"view_cost.py: unpaired runs in {raw}")
    cpu = [view_cpu_percent(r) for r in with_view]
    received = [json.loads((r / "client.json").read_text())["topics"] for r in with_view]
    rows = []
    for stage in stages(without[0]):
        if any(stages(r)[stage].get("count", 0) == 0 for r in without + with_view):
            continue  # (a stage no frame crossed in some run)
        row = {"stage": stage}
        for key in ("p50_ms", "p99_ms"):
            row[f"without_{key}"] = statistics.median(stages(r)[stage][key] for r in without)
            row[f"with_{key}"] = statistics.median(stages(r)[stage][key] for r in with_view)
            row[f"ratio_{key}"] = row[f"with_{key}"] / row[f"without_{key}"] if row[f"without_{key}"] else float("nan")
        rows.append(row)
    columns = list(rows[0].keys())
    with open(out / "view_cost.csv", "w") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(row["stage"] if c == "stage" else f"{row[c]:.3f}" for c in columns) + "\n")
    print(f"view CPU: {statistics.median(cpu):.1f} % of one core (median of {len(cpu)} runs: "
          + ", ".join(f"{c:.1f}" for c in cpu) + ")")
    for topic in ("/overlay", "/camera/image", "/world"):
        counts = [r[topic]["count"] for r in received]
        print(f"client received {topic}: " + ", ".join(str(c) for c in counts) + " messages")
    print(f"{'stage':28} {'p50 without':>12} {'with':>8} {'ratio':>6} {'p99 without':>12} {'with':>8} {'ratio':>6}")
    for r in rows:
        print(f"{r['stage']:28} {r['without_p50_ms']:12.2f} {r['with_p50_ms']:8.2f} {r['ratio_p50_ms']:6.2f} "
              f"{r['without_p99_ms']:12.2f} {r['with_p99_ms']:8.2f} {r['ratio_p99_ms']:6.2f}")


if __name__ == "__main__":
    main()
