#!/usr/bin/env python3
"""Turns bench/results.csv and bench/scaling.csv into bench/RESULTS.md and the pictures in bench/figures/.

  python3 bench/report.py [--dir bench] [--bench build/bin/rattle-bench] [--matrix-seconds S] [--load A,B]

run_matrix.py calls it at the end of `make bench`; run alone it redoes the report from the CSVs already there.
Pictures are drawn by gnuplot (pngcairo); its data and script go to a temporary folder that is removed.
"""
import argparse
import csv
import datetime
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile

ENGINES = ["discrete", "hybrid", "predictive", "bisect", "box2d", "box2d-bullet", "chipmunk"]
FLOOR = 1e-17        # where a zero relative error is drawn on a log axis
FRACTION_FLOOR = 1e-4  # where a zero fraction of bodies is drawn
# Notes every row of an engine carries, said once in the report's header instead of in every table row.
HEADER_NOTES = ("libchipmunk is a debug build",)

# ---------------------------------------------------------------------------------------------------------
# Reading


def num(row, key):
    v = row.get(key, "")
    try:
        return float(v)
    except ValueError:
        return float("nan")


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def step_name(dt):
    """1/60 for 0.016666..., else the number."""
    inv = 1.0 / dt
    if abs(inv - round(inv)) < 1e-6 * inv and inv >= 1:
        return "1/%d" % round(inv)
    return "%g" % dt


def fmt(v, kind="g"):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if kind == "ms":
        return "%.3g" % v if v < 1000 else "%.0f" % v
    if kind == "e":
        return "0" if v == 0 else "%.1e" % v
    if kind == "int":
        return "%d" % v
    if kind == "rate":
        return "%.3g" % v
    return "%.3g" % v


# ---------------------------------------------------------------------------------------------------------
# Tables


def scene_tables(rows):
    """Groups rows into the report's tables: (key, title, rows)."""
    tables = []
    seen = []
    for r in rows:
        scene = r["scene"]
        if r.get("table") == "pile-target" or (scene == "pile" and r.get("table") is None and
                                                 r.get("collapse_time") == ""):
            key = "pile-target"
            title = "pile, %s disks for %s s at dt 1/60, every engine's default settings (issue 24's targets)" % (
                r["n"], r["seconds"])
        elif r.get("table") == "pile-sleep":
            key = "pile-sleep"
            title = "pile, %s disks for %s s at dt 1/60, hybrid (issue 24's target: every body asleep by 10 s)" % (
                r["n"], r["seconds"])
        elif scene == "crowd":
            key = "crowd-%s" % r["n"]
            title = "crowd, %s disks steered naively through two doorways" % r["n"]
        elif scene == "gas":
            key = "gas-%s" % r["packing"]
            title = "gas, %s disks, packing %s, speed 1" % (r["n"], r["packing"])
        elif scene == "bullets":
            key = "bullets"
            title = "bullets, %s disks of radius 0.05 in a 20 x 20 box, one run per speed" % r["n"]
        elif scene == "arena":
            key = "arena-%s" % r["n"]
            title = "arena, the demo's game with %s units per team for %s s" % (r["n"], r["seconds"])
        else:
            key = scene
            title = {"pile": "pile, %s disks poured under gravity, restitution 0.5",
                     "cradle": "cradle, %s disks (Newton's cradles in lanes)",
                     "sensors": "sensors, %s disks crossing six thin sensor strips"}[scene] % r["n"]
        if key not in seen:
            seen.append(key)
            tables.append((key, title, []))
        tables[seen.index(key)][2].append(r)
    return tables


def order(rows):
    return sorted(rows, key=lambda r: (ENGINES.index(r["engine"]) if r["engine"] in ENGINES else 99,
                                       -num(r, "dt"), num(r, "speed")))


def row_notes(r):
    notes = r.get("notes", "")
    return "" if notes.startswith(HEADER_NOTES) else notes.replace("|", "/")


def step_cells(r):
    """The step times beside the median: the 99th percentile and the worst step (after warm-up)."""
    return [fmt(num(r, "p99_ms_per_step"), "ms"), fmt(num(r, "worst_ms_per_step"), "ms")]


def stopped(r):
    return r.get("stopped_at_time_limit") == "yes"


def crowd_table(rows):
    """The crowd: step times, Chipmunk's median over each engine's (measured in the same run), and how the
    crowd fared: through the doorways, overlaps, through walls."""
    chip = [r for r in rows if r["engine"] == "chipmunk"]
    base = num(chip[0], "ms_per_step") if chip else float("nan")
    head = ["engine", "simulated s", "ms/step (median)", "p99 ms", "worst ms", "mean ms", "median / Chipmunk's",
            "reached goal", "max overlap", "mean overlap", "through a wall", "notes"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in order(rows):
        secs = "%g%s" % (num(r, "seconds"), " (stopped at the time limit)" if stopped(r) else "")
        cells = [r["engine"], secs, fmt(num(r, "ms_per_step"), "ms")] + step_cells(r) + \
                [fmt(mean_step(r), "ms"), fmt(num(r, "ms_per_step") / base) + "x",
                 "%s of %s" % (r.get("reached_goal", ""), r["n"]), fmt(num(r, "max_overlap"), "e"),
                 fmt(num(r, "mean_overlap"), "e"), r["tunnelled"], row_notes(r)]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def generic_table(rows):
    has_sensors = any(r.get("sensor_missed", "") != "" for r in rows)
    has_asleep = any(r.get("asleep", "") != "" for r in rows)
    head = ["engine", "dt", "ms/step", "p99 ms", "worst ms", "ms/sim s", "collisions/s", "energy drift", "max overlap", "mean overlap",
            "tunnelled"] + (["sensor missed"] if has_sensors else []) + (["asleep at the end"] if has_asleep else []) + \
           ["count error", "notes"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in order(rows):
        cells = [r["engine"], step_name(num(r, "dt")), fmt(num(r, "ms_per_step"), "ms")] + step_cells(r) + \
                [fmt(num(r, "ms_per_simulated_second"), "ms"), fmt(num(r, "collisions_per_s"), "rate"),
                 fmt(num(r, "energy_drift"), "e"), fmt(num(r, "max_overlap"), "e"), fmt(num(r, "mean_overlap"), "e"),
                 r["tunnelled"]]
        if has_sensors:
            missed = r.get("sensor_missed", "")
            cells.append("%s of %s" % (missed, r.get("reference_sensor_visits", "")) if missed != "" else "-")
        if has_asleep:
            cells.append("%s of %s" % (r["asleep"], r["n"]) if r.get("asleep", "") != "" else "-")
        cells += [fmt(num(r, "collision_count_error"), "e"), row_notes(r)]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def arena_table(rows):
    """The demo's game: its own error measures, and step time as a ratio to the discrete mode's in this run."""
    discrete = [r for r in rows if r["engine"] == "discrete"]
    base = num(discrete[0], "ms_per_step") if discrete else float("nan")
    head = ["engine", "ms/step", "p99 ms", "worst ms", "x discrete", "ms/sim s", "contacts/s", "shots tunnelled", "shots out of range",
            "max overlap", "mean overlap", "sensor missed", "contact count error", "notes"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in order(rows):
        ref = r.get("reference_shots_out_of_range", "")
        cells = [r["engine"], fmt(num(r, "ms_per_step"), "ms")] + step_cells(r) + [fmt(num(r, "ms_per_step") / base),
                 fmt(num(r, "ms_per_simulated_second"), "ms"), fmt(num(r, "collisions_per_s"), "rate"),
                 "%s of %s" % (r["tunnelled"], r.get("shots", "")),
                 "%s of %s" % (r.get("shots_out_of_range", ""), r.get("shots", "")) +
                 (" (predictive game: %s of %s)" % (ref, r.get("reference_shots", "")) if ref != "" and
                  r["engine"] != "predictive" else ""),
                 fmt(num(r, "max_overlap"), "e"), fmt(num(r, "mean_overlap"), "e"),
                 "%s of %s" % (r["sensor_missed"], r.get("reference_sensor_visits", "")),
                 fmt(num(r, "collision_count_error"), "e"), row_notes(r)]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def bullets_table(rows):
    speeds = sorted({num(r, "speed") for r in rows})
    head = ["engine", "dt"] + ["tunnelled @%g" % v for v in speeds] + \
           ["ms/step @%g" % speeds[-1], "p99 ms @%g" % speeds[-1], "worst ms @%g" % speeds[-1],
            "ms/sim s @%g" % speeds[-1], "energy drift @%g" % speeds[-1], "max overlap @%g" % speeds[-1], "notes"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    by = {}
    for r in rows:
        by.setdefault((r["engine"], r["dt"]), {})[num(r, "speed")] = r
    keys = sorted(by, key=lambda k: (ENGINES.index(k[0]) if k[0] in ENGINES else 99, -float(k[1])))
    for k in keys:
        runs = by[k]
        fast = runs.get(speeds[-1], {})
        notes = sorted({row_notes(runs[v]) for v in runs} - {""})
        cells = [k[0], step_name(float(k[1]))] + \
                ["%s/%s" % (runs[v]["tunnelled"], runs[v]["n"]) if v in runs else "-" for v in speeds] + \
                [fmt(num(fast, "ms_per_step"), "ms")] + step_cells(fast) + \
                [fmt(num(fast, "ms_per_simulated_second"), "ms"), fmt(num(fast, "energy_drift"), "e"),
                 fmt(num(fast, "max_overlap"), "e"), "; ".join(notes).replace("|", "/")]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------------------
# Pictures (gnuplot)

# Per table: the two error measures drawn, as (label, function of a row -> value, floor).
def measures(key):
    frac = lambda col: (lambda r: num(r, col) / num(r, "n"))
    absol = lambda col: (lambda r: abs(num(r, col)))
    missed = lambda r: (num(r, "sensor_missed") / num(r, "reference_sensor_visits")
                        if num(r, "reference_sensor_visits") > 0 else float("nan"))
    if key.startswith("gas"):
        return [("max overlap / radius", absol("max_overlap"), FLOOR),
                ("|collision count error|", absol("collision_count_error"), FLOOR)]
    if key.startswith("crowd"):
        behind = lambda r: 1 - num(r, "reached_goal") / num(r, "n")
        return [("max overlap / radius", absol("max_overlap"), FLOOR),
                ("fraction of disks that did not reach the goal", behind, FRACTION_FLOOR)]
    if key.startswith("pile"):
        return [("max overlap / radius", absol("max_overlap"), FLOOR),
                ("fraction of disks tunnelled", frac("tunnelled"), FRACTION_FLOOR)]
    if key == "bullets":
        return [("fraction of bullets tunnelled (speed 10^4)", frac("tunnelled"), FRACTION_FLOOR),
                ("|energy drift| (speed 10^4)", absol("energy_drift"), FLOOR)]
    if key.startswith("arena"):
        shots = lambda r: num(r, "tunnelled") / num(r, "shots") if num(r, "shots") > 0 else float("nan")
        return [("fraction of shots tunnelled", shots, FRACTION_FLOOR),
                ("max overlap / radius", absol("max_overlap"), FLOOR)]
    if key == "cradle":
        return [("|collision count error|", absol("collision_count_error"), FLOOR),
                ("|energy drift|", absol("energy_drift"), FLOOR)]
    return [("fraction of sensor visits missed", missed, FRACTION_FLOOR),
            ("fraction of disks tunnelled", frac("tunnelled"), FRACTION_FLOOR)]


def gnuplot(script, tmp):
    path = os.path.join(tmp, "plot.gp")
    with open(path, "w") as f:
        f.write(script)
    p = subprocess.run(["gnuplot", path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("gnuplot failed: " + p.stderr[-500:])


def speed_error_figure(key, title, rows, png, tmp):
    if key == "bullets":
        fastest = max(num(r, "speed") for r in rows)
        rows = [r for r in rows if num(r, "speed") == fastest]
    panels = []
    for p, (label, value, floor) in enumerate(measures(key)):
        plots = []
        for i, engine in enumerate(ENGINES):
            pts = [r for r in order(rows) if r["engine"] == engine]
            pts = [(max(value(r), floor), num(r, "ms_per_simulated_second"), step_name(num(r, "dt")))
                   for r in pts if not math.isnan(value(r)) and num(r, "ms_per_simulated_second") > 0]
            if not pts:
                continue
            data = os.path.join(tmp, "%s-%d-%s.dat" % (key, p, engine))
            with open(data, "w") as f:
                for x, y, lab in pts:
                    f.write("%.6e %.6e %s\n" % (x, y, lab))
            plots.append("'%s' using 1:2 with linespoints ls %d title '%s'" % (data, i + 1, engine))
            plots.append("'%s' using 1:2:3 with labels offset 0.6,0.6 font ',7' tc ls %d notitle" % (data, i + 1))
        panels.append((label, floor, plots))
    styles = "\n".join("set style line %d lc rgb '%s' pt %d ps 1.2 lw 1.2" % (i + 1, c, pt) for i, (c, pt) in
                       enumerate([("#1b9e77", 4), ("#d95f02", 7), ("#7570b3", 5), ("#e7298a", 9),
                                  ("#66a61e", 6), ("#a6761d", 8), ("#666666", 12)]))
    script = ["set terminal pngcairo size 1400,560 font ',10'", "set output '%s'" % png, styles,
              "set logscale xy", "set format x '10^{%L}'", "set format y '10^{%L}'", "set grid",
              "set key outside right top", "set multiplot layout 1,2 title \"%s: time against error "
              "(points labelled by step; lower left is better)\"" % title.replace('"', "'")]
    for p, (label, floor, plots) in enumerate(panels):
        if p > 0:
            script.append("unset key")  # the first panel's key names the engines for both
        script.append("set xlabel \"%s (0 drawn at %g)\"" % (label, floor))
        script.append("set ylabel 'ms of step time per simulated second'")
        script.append("plot " + ", \\\n  ".join(plots) if plots else "plot 1/0 notitle")
    script.append("unset multiplot")
    gnuplot("\n".join(script) + "\n", tmp)


def fit_slope(points):
    """Least-squares slope of log y against log x."""
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def scaling_series(rows):
    hybrid = sorted((num(r, "n"), mean_step(r)) for r in rows if r["series"] == "hybrid")
    pred = {}
    for s in ("predictive-one-look", "predictive-1/60", "edmd-one-look", "edmd-lean-one-look"):
        pts = []
        for r in rows:
            # collisions_per_s: the collisions of the timed steps over their CPU time (after warm-up).
            if r["series"] == s and num(r, "collisions_per_s") > 0:
                pts.append((num(r, "n"), 1e6 / num(r, "collisions_per_s")))  # microseconds per collision
        pred[s] = sorted(pts)
    return hybrid, pred


def scaling_figure(rows, png, tmp):
    hybrid, pred = scaling_series(rows)
    def dat(name, pts):
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            for x, y in pts:
                f.write("%.6e %.6e\n" % (x, y))
        return path
    h = dat("hybrid.dat", hybrid)
    p1 = dat("pred1.dat", pred["predictive-one-look"])
    p2 = dat("pred60.dat", pred["predictive-1/60"])
    p3 = dat("edmd.dat", pred["edmd-one-look"])
    p4 = dat("edmdlean.dat", pred["edmd-lean-one-look"])
    x0, y0 = hybrid[0] if hybrid else (1, 1)
    script = """set terminal pngcairo size 1400,560 font ',10'
set output '%s'
set logscale xy
set format x '10^{%%L}'
set grid
set key top left
set multiplot layout 1,2 title "rattle scaling on gas (time of step() only)"
set xlabel 'disks'
set ylabel 'ms per step (dt = 1/60, packing 0.3)'
plot '%s' using 1:2 with linespoints pt 7 lw 1.5 title 'hybrid', %g*x/%g with lines dt 2 lc rgb '#888888' title 'proportional to N'
set ylabel 'microseconds of step time per collision (packing 0.5)'
plot '%s' using 1:2 with linespoints pt 7 lw 1.5 title 'predictive, one look at the end', \\
     '%s' using 1:2 with linespoints pt 5 lw 1.5 title 'predictive, a look every 1/60 s', \\
     '%s' using 1:2 with linespoints pt 9 lw 1.5 dt 3 title 'baseline: textbook event-driven gas (edmd), one look', \\
     '%s' using 1:2 with linespoints pt 11 lw 1.5 dt 4 title 'baseline: event-driven gas written for speed (edmd-lean), one look'
unset multiplot
""" % (png, h, y0, x0, p1, p2, p3, p4)
    gnuplot(script, tmp)
    return hybrid, pred


# ---------------------------------------------------------------------------------------------------------
# Targets


def find(rows, **want):
    for r in rows:
        if all((abs(num(r, k) - v) <= 1e-9 * abs(v)) if isinstance(v, float) else r.get(k) == v
               for k, v in want.items()):
            return r
    return None


def mean_step(r):
    """The mean CPU time of a step after warm-up, in ms (ms_per_simulated_second times dt). The speed
    targets are judged by it, not by the median (ms_per_step): the hybrid's steps are not alike, since one
    served from the broad phase's pair cache costs less than one that sweeps, and the median of such a
    mix is the cheaper kind's."""
    return num(r, "ms_per_simulated_second") * num(r, "dt")


def repeat_times(repeat_rows):
    """{repeat: {engine: mean step time}} from repeats.csv."""
    by_repeat = {}
    for r in repeat_rows:
        by_repeat.setdefault(r["repeat"], {})[r["engine"]] = mean_step(r)
    return by_repeat


def repeat_ratios(repeat_rows):
    """{engine: [its mean step time / hybrid's, one per repeat]} for box2d and chipmunk, from repeats.csv."""
    ratios = {"box2d": [], "chipmunk": []}
    for times in repeat_times(repeat_rows).values():
        for engine in ratios:
            if "hybrid" in times and engine in times and times["hybrid"] > 0:
                ratios[engine].append(times[engine] / times["hybrid"])
    return ratios


def repeats_table(repeat_rows):
    by_repeat = repeat_times(repeat_rows)
    out = ["| repeat | hybrid ms/step (mean) | Box2D ms/step (mean) | Chipmunk ms/step (mean) | Box2D / hybrid | "
           "Chipmunk / hybrid |",
           "|---|---|---|---|---|---|"]
    for k in sorted(by_repeat, key=int):
        t = by_repeat[k]
        h = t.get("hybrid", float("nan"))
        cell = lambda e: "%.3f" % t[e] if e in t else "-"
        ratio = lambda e: "%.1fx" % (t[e] / h) if e in t and h > 0 else "-"
        out.append("| %s | %s | %s | %s | %s | %s |" % (k, cell("hybrid"), cell("box2d"), cell("chipmunk"),
                                                        ratio("box2d"), ratio("chipmunk")))
    return "\n".join(out)


def targets(rows, scaling_rows, repeat_rows=()):
    out = ["| target | measured (CPU time of the step) | met |", "|---|---|---|"]
    dt60 = 1 / 60
    h = find(rows, scene="gas", engine="hybrid", packing="0.3", dt=dt60)
    b = find(rows, scene="gas", engine="box2d", packing="0.3", dt=dt60)
    c = find(rows, scene="gas", engine="chipmunk", packing="0.3", dt=dt60)
    ratios = repeat_ratios(repeat_rows)

    def speed_target(other, engine, times):
        """The matrix run's ratio, then the repeats' median and range; met by the median when there are
        repeats (one run's ratio moves with the machine), else by the matrix run's."""
        ratio = mean_step(other) / hm
        text = "mean step %.3f ms vs %.2f ms: %.1fx (medians %.3f ms vs %.2f ms: %.1fx)%s" % (
            hm, mean_step(other), ratio, num(h, "ms_per_step"), num(other, "ms_per_step"),
            num(other, "ms_per_step") / num(h, "ms_per_step"), wall(other))
        verdict = ratio
        rs = sorted(ratios[engine])
        if rs:
            verdict = statistics.median(rs)
            text += "; over %d repeats (below): median **%.1fx**, %.1fx to %.1fx" % (len(rs), verdict, rs[0], rs[-1])
        else:
            text = text.replace(": %.1fx (" % ratio, ": **%.1fx** (" % ratio, 1)
        return text, "yes" if verdict >= times else "**no**"

    if h:
        n = h["n"]
        hm = mean_step(h)
        def wall(other):
            w = num(other, "wall_ms_per_step") / num(h, "wall_ms_per_step")
            return "" if math.isnan(w) else " (wall-clock medians: %.2f ms vs %.2f ms, %.1fx)" % (
                num(h, "wall_ms_per_step"), num(other, "wall_ms_per_step"), w)
        if b:
            text, met = speed_target(b, "box2d", 10)
            out.append("| gas %s, packing 0.3, dt 1/60: hybrid >= 10x faster per step than Box2D 2.4 default | "
                       "%s | %s |" % (n, text, met))
        if c:
            text, met = speed_target(c, "chipmunk", 3)
            out.append("| same scene: hybrid >= 3x faster per step than Chipmunk 7 | %s | %s |" % (text, met))
        t, d, o = int(num(h, "tunnelled")), abs(num(h, "energy_drift")), num(h, "max_overlap")
        out.append("| same scene: hybrid tunnels 0, energy drift < 1e-9, max overlap < 1e-9 of a radius | "
                   "tunnelled %d, drift %.1e, max overlap %.1e | %s |" %
                   (t, num(h, "energy_drift"), o, "yes" if t == 0 and d < 1e-9 and o < 1e-9 else "**no**"))
        for other, name in ((b, "Box2D"), (c, "Chipmunk")):
            if other:
                out.append("| (for scale) %s on the same scene | drift %.1e, max overlap %.2f, mean overlap %.1e, "
                           "tunnelled %s | - |" % (name, num(other, "energy_drift"), num(other, "max_overlap"),
                                                   num(other, "mean_overlap"), other["tunnelled"]))
    bl = [r for r in rows if r["scene"] == "bullets" and r["engine"] in ("hybrid", "predictive")]
    if bl:
        tunnelled = sum(int(num(r, "tunnelled")) for r in bl)
        speeds = sorted({num(r, "speed") for r in bl})
        out.append("| bullets: hybrid and predictive tunnel 0 times at every speed | %d tunnelled over %d runs "
                   "(speeds %s, dt 1/30..1/240) | %s |" % (tunnelled, len(bl), ", ".join("%g" % s for s in speeds),
                                                            "yes" if tunnelled == 0 else "**no**"))
    ar = [r for r in rows if r["scene"] == "arena" and r["engine"] in ("hybrid", "predictive")]
    if ar:
        tunnelled = sum(int(num(r, "tunnelled")) for r in ar)
        shots = sum(int(num(r, "shots")) for r in ar)
        out.append("| arena: hybrid and predictive shoot no projectile through a wall | %d tunnelled of %d shots over "
                   "%d runs | %s |" % (tunnelled, shots, len(ar), "yes" if tunnelled == 0 else "**no**"))
    def repeated(series, n, value, unit):
        """The values of the scaling run of `series` at `n` disks and of its repeats (series + "-repeat"),
        the scaling run's first: (verdict, text). The verdict is their median; with one run, that run's."""
        values = [value(r) for r in scaling_rows if r["series"] in (series, series + "-repeat") and
                  r.get("n") == n]
        if len(values) < 2:
            return values[0], ""
        rs = sorted(values)
        return statistics.median(rs), "; over %d runs (the scaling run and %d repeats, in turn with the other " \
            "target's): median **%s**, %s to %s" % (len(rs), len(rs) - 1, unit(statistics.median(rs)),
                                                    unit(rs[0]), unit(rs[-1]))

    def paired_with_lean():
        """Predictive's rate over edmd-lean's, pair by pair, at 10^5 disks with one look: each edmd-lean row
        (the scaling run's, then each repeat's) with the predictive row run just before it (scaling.csv is
        in run order; a pair one of whose runs failed is left out)."""
        ratios, waiting = [], None
        for r in scaling_rows:
            if r.get("n") != "100000":
                continue
            if r["series"] in ("predictive-one-look", "predictive-one-look-repeat"):
                waiting = r
            elif r["series"] in ("edmd-lean-one-look", "edmd-lean-one-look-repeat") and waiting is not None:
                lean_rate = num(r, "collisions_per_s")
                if lean_rate > 0:  # (nan, or no collisions timed: no ratio)
                    ratios.append(num(waiting, "collisions_per_s") / lean_rate)
                waiting = None
        return sorted(x for x in ratios if math.isfinite(x))

    for series, what in (("predictive-one-look", "one look at the end"), ("predictive-1/60", "a look every 1/60 s")):
        p = find(scaling_rows, series=series, n="100000")
        e = find(scaling_rows, series="edmd-one-look", n="100000")
        lean = find(scaling_rows, series="edmd-lean-one-look", n="100000")
        if p:
            rate = num(p, "collisions_per_s")
            baseline = ""
            if e:
                baseline = "; the textbook baseline (edmd) in this run: %.3g collisions/s (%s timed collisions), " \
                           "so predictive is %.2fx its rate" % (num(e, "collisions_per_s"), e["timed_collisions"],
                                                                rate / num(e, "collisions_per_s"))
            if lean:
                baseline += "; the baseline written for speed alone (edmd-lean): %.3g collisions/s, so " \
                            "predictive is %.2fx its rate" % (num(lean, "collisions_per_s"),
                                                              rate / num(lean, "collisions_per_s"))
            pairs = paired_with_lean() if series == "predictive-one-look" else []
            if len(pairs) > 1:
                baseline += "; run in pairs with edmd-lean (each predictive run followed by one of edmd-lean), " \
                            "predictive's rate over edmd-lean's: median **%.2fx** over %d pairs, %.2fx to %.2fx" % (
                                statistics.median(pairs), len(pairs), pairs[0], pairs[-1])
            verdict, spread = repeated(series, "100000", lambda r: num(r, "collisions_per_s"),
                                       lambda v: "%.3g collisions/s" % v)
            out.append("| predictive gas 10^5, packing 0.5: >= 2e6 collisions per second (%s) | %.3g collisions/s "
                       "(%s collisions in the %g s timed after %s s of warm-up)%s%s | %s |" %
                       (what, rate, p["timed_collisions"], num(p, "seconds") - num(p, "warm_up_s"),
                        p.get("warm_up_s") or "0", baseline, spread, "yes" if verdict >= 2e6 else "**no**"))
    g = find(scaling_rows, series="hybrid", n="1000000")
    if g:
        ns = mean_step(g) * 1e6 / num(g, "n")
        verdict, spread = repeated("hybrid", "1000000", lambda r: mean_step(r) * 1e6 / num(r, "n"),
                                   lambda v: "%.0f ns" % v)
        out.append("| hybrid gas 10^6, packing 0.3, dt 1/60: runs, < 100 ns per disk per step | %.1f ms per step "
                   "(mean; median %.1f ms): %s ns per disk per step (tunnelled %s, drift %.1e)%s | %s |" %
                   (mean_step(g), num(g, "ms_per_step"), ("%.0f" if spread else "**%.0f**") % ns, g["tunnelled"],
                    num(g, "energy_drift"), spread, "yes" if verdict < 100 else "**no**"))
    return "\n".join(out)


def targets_issue24(rows):
    """Issue 24's targets (crowds and piles in bounded time), judged as ratios within this run. A row stopped
    at its wall-clock limit did not finish its run: its targets are not met, and its counts cover only the
    stretch it ran."""
    out = ["| target | measured (CPU time of the step) | met |", "|---|---|---|"]
    yes = lambda ok: "yes" if ok else "**no**"
    pile = [r for r in rows if r.get("table") == "pile-target" or (r.get("table") is None and r["scene"] == "pile"
                                                                    and r.get("collapse_time") == "")]
    pick = lambda rs, engine: next((r for r in rs if r["engine"] == engine), None)

    def ran(r):
        return "ran only %g s: stopped at the wall-clock limit" % num(r, "seconds") if stopped(r) else ""

    def steps(r):
        return "median %s ms, p99 %s ms, worst %s ms, mean %s ms" % (
            fmt(num(r, "ms_per_step"), "ms"), fmt(num(r, "p99_ms_per_step"), "ms"),
            fmt(num(r, "worst_ms_per_step"), "ms"), fmt(mean_step(r), "ms"))

    h, p, b, c = (pick(pile, e) for e in ("hybrid", "predictive", "box2d", "chipmunk"))
    if h:
        what = "pile %s, %g s, dt 1/60, restitution 0.5, default settings, hybrid" % (h["n"], num(h, "seconds"))
        done = not stopped(h)
        note = (" (%s)" % ran(h)) if not done else ""
        for other, name, limit in ((c, "Chipmunk", 0.5), (b, "Box2D 2.4", 0.2)):
            if other:
                ratio = mean_step(h) / mean_step(other)
                out.append("| %s: mean step <= %gx %s's | mean step %.3g ms vs %.3g ms: **%.2fx**%s%s | %s |" % (
                    what, limit, name, mean_step(h), mean_step(other), ratio, note,
                    (" (%s: %s)" % (name, ran(other))) if stopped(other) else "",
                    yes(done and not stopped(other) and ratio <= limit)))
            else:
                out.append("| %s: mean step <= %gx %s's | no %s row in this run | **no** |" % (what, limit, name, name))
        w = num(h, "worst_ms_per_step") / num(h, "ms_per_step")
        out.append("| same pile, hybrid: worst step <= 5x its own median | %s: worst **%.1fx** the median%s | %s |" %
                   (steps(h), w, note, yes(done and w <= 5)))
        o = num(h, "max_overlap")
        out.append("| same pile, hybrid: max overlap <= 1%% of a radius | max overlap %.2e of a radius%s | %s |" %
                   (o, note, yes(done and o <= 0.01)))
        t = int(num(h, "tunnelled"))
        out.append("| same pile, hybrid: nothing below the floor | %d disks outside the box%s | %s |" %
                   (t, note, yes(done and t == 0)))
        # The pile-sleep row runs the same pile to 10 s; without one, the 8 s row can only tell a yes.
        sleep = next((r for r in rows if r.get("table") == "pile-sleep" and r["engine"] == "hybrid"), None)
        for row, last in ((h, False), (sleep, True)):
            asleep = row.get("asleep", "") if row else ""
            if asleep == "" or (not last and int(asleep) != int(row["n"]) and sleep):
                continue
            row_done = not stopped(row)
            if int(asleep) == int(row["n"]) and row_done:
                out.append("| same pile, hybrid: every body asleep by 10 s | all %s asleep at %g s | yes |" %
                           (asleep, num(row, "seconds")))
            elif num(row, "seconds") >= 10 and row_done:
                out.append("| same pile, hybrid: every body asleep by 10 s | %s of %s asleep at %g s | **no** |" %
                           (asleep, row["n"], num(row, "seconds")))
            else:
                out.append("| same pile, hybrid: every body asleep by 10 s | %s of %s asleep at the end of the row "
                           "(%g s); the row does not run to 10 s%s | cannot tell |" %
                           (asleep, row["n"], num(row, "seconds"), (" (%s)" % ran(row)) if not row_done else ""))
            break
        else:
            out.append("| same pile, hybrid: every body asleep by 10 s | no row says | cannot tell |")
    if p:
        done = not stopped(p)
        out.append("| same pile, predictive, default settings: completes | %s%s | %s |" % (
            ran(p) or "ran all %g s (%s steps)" % (num(p, "seconds"), p["steps"]),
            "; " + row_notes(p) if row_notes(p) and not stopped(p) else "", yes(done)))
        if h:
            ratio = mean_step(p) / mean_step(h)
            out.append("| same pile, predictive: mean step <= 2x the hybrid's | mean step %.3g ms vs %.3g ms: "
                       "**%.2fx**%s | %s |" % (mean_step(p), mean_step(h), ratio,
                                              (" (predictive %s)" % ran(p)) if not done else "",
                                              yes(done and not stopped(h) and ratio <= 2)))
    crowd = [r for r in rows if r["scene"] == "crowd"]
    if crowd:
        n = max(int(num(r, "n")) for r in crowd)
        big = [r for r in crowd if int(num(r, "n")) == n]
        h, c = pick(big, "hybrid"), pick(big, "chipmunk")
        what = "crowd of %d, naive steering, dt 1/30" % n
        if h:
            done = not stopped(h)
            note = (" (%s)" % ran(h)) if not done else ""
            if c:
                ratio = num(h, "ms_per_step") / num(c, "ms_per_step")
                out.append("| %s, hybrid: median step <= 0.5x Chipmunk's | %s vs Chipmunk's median %s ms: **%.2fx**%s%s"
                           " | %s |" % (what, steps(h), fmt(num(c, "ms_per_step"), "ms"), ratio, note,
                                        (" (Chipmunk %s)" % ran(c)) if stopped(c) else "",
                                        yes(done and not stopped(c) and ratio <= 0.5)))
            w = num(h, "worst_ms_per_step") / num(h, "ms_per_step")
            out.append("| same crowd, hybrid: worst step <= 5x the median | ran %g s; worst **%.1fx** the median%s | %s |" %
                       (num(h, "seconds"), w, note, yes(done and w <= 5)))
            o = num(h, "max_overlap")
            out.append("| same crowd, hybrid: max overlap <= 1%% of a radius | max overlap %.2e of a radius%s | %s |" %
                       (o, note, yes(done and o <= 0.01)))
            t = int(num(h, "tunnelled"))
            out.append("| same crowd, hybrid: none through a wall | %d through a wall%s | %s |" %
                       (t, note, yes(done and t == 0)))
            if c:
                rh, rc = int(num(h, "reached_goal")), int(num(c, "reached_goal"))
                out.append("| same crowd, hybrid: at least as many disks through the doorway as Chipmunk lets through | "
                           "%d against Chipmunk's %d%s | %s |" % (rh, rc, note, yes(done and not stopped(c) and rh >= rc)))
            out.append(doorway_capacity_row(big, num(h, "seconds")))
        else:
            out.append("| %s, hybrid | no hybrid row in this run | **no** |" % what)
    if len(out) == 2:
        out.append("| issue 24's rows (tables pile-target and crowd) | not in this run | - |")
    return "\n".join(out)


def doorway_capacity_row(rows, seconds):
    """What disks that never overlap can pass through the crowd's doorways, against each engine's count.

    Disks of radius r packed as densely as disks can be (hexagonal: one per 2 sqrt(3) r^2 of area) moving
    at the steering's full speed v straight through doorways of total width W carry about
    v W T / (2 sqrt(3) r^2) of them across in T seconds; the flow of a real jam is slower (the centres keep
    a radius from the jambs, the disks leave the doorway fanning out). An engine that counts more lets its
    disks overlap or pass through the wall. The scene's sizes are scenes/scenes.h's: r 0.5, two doorways
    4 wide, v 3 (rattle-bench --speed).
    """
    r, width, speed = 0.5, 2 * 4.0, 3.0
    bound = speed * width * seconds / (2 * math.sqrt(3) * r * r)
    counts = []
    for engine in ["hybrid", "predictive", "discrete", "box2d", "chipmunk"]:
        row = next((x for x in rows if x["engine"] == engine), None)
        if not row or row.get("reached_goal", "") == "":
            continue
        counts.append("%s %d (max overlap %.2g radii, %d through a wall)" % (
            engine, int(num(row, "reached_goal")), num(row, "max_overlap"), int(num(row, "tunnelled"))))
    return ("| same crowd: what disks that never overlap can pass | densest packing at full speed through both "
            "doorways: about %d in %g s; %s | - |" % (bound, seconds, "; ".join(counts)))


# ---------------------------------------------------------------------------------------------------------
# The report


def machine(bench):
    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    version = "?"
    if bench and os.access(bench, os.X_OK):
        version = subprocess.run([bench, "--version"], capture_output=True, text=True).stdout.strip()
    return cpu, os.cpu_count(), version


def commit(root):
    try:
        rev = subprocess.run(["git", "-C", root, "rev-parse", "--short=12", "HEAD"], capture_output=True,
                             text=True).stdout.strip()
        # The bench's own outputs, just written, are not changes to what was measured.
        outputs = ("bench/results.csv", "bench/scaling.csv", "bench/repeats.csv", "bench/RESULTS.md",
                   "bench/figures/")
        status = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no"],
                                capture_output=True, text=True).stdout.splitlines()
        dirty = [line for line in status if not line[3:].startswith(outputs)]
        return rev + (" (with uncommitted changes)" if dirty else "") if rev else "?"
    except OSError:
        return "?"


def write_report(out_dir, bench, matrix_seconds=None, load=None):
    rows = read_csv(os.path.join(out_dir, "results.csv"))
    scaling_rows = read_csv(os.path.join(out_dir, "scaling.csv"))
    repeat_rows = read_csv(os.path.join(out_dir, "repeats.csv"))
    if not rows and not scaling_rows:
        sys.exit("report: no results.csv or scaling.csv in %s; run bench/run_matrix.py first" % out_dir)
    if not shutil.which("gnuplot"):
        sys.exit("report: gnuplot is missing (bash scripts/install-deps.sh scripts/packages-bench.txt)")
    figures = os.path.join(out_dir, "figures")
    os.makedirs(figures, exist_ok=True)
    root = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    cpu, cores, version = machine(bench)
    md = ["# rattle-bench results", "",
          "Written by `make bench` (bench/run_matrix.py, then bench/report.py); bench/README.md says what every "
          "column measures and how. Raw rows: [results.csv](results.csv), [scaling.csv](scaling.csv).", "",
          "- date: %s" % datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
          "- commit: %s" % commit(root),
          "- machine: %s, %s cores (runs are single-threaded, one at a time)%s" %
          (cpu, cores, "; load average %s at the start and %s at the end of the matrix (other work on the "
                       "machine slows every engine alike, but adds noise)" % (load[0], load[1]) if load else ""),
          "- build: %s" % version.replace("\n", "; "),
          ]
    if matrix_seconds is not None:
        md.append("- the matrix took %.0f s" % matrix_seconds)
    md += ["", "Read with these in mind (bench/README.md has the details):", "",
           "- Only step() is timed, by the CPU time of its thread (so other work on the machine does not count "
           "as the engine's; results.csv has the wall-clock median too); every error is measured outside it. "
           "A shared machine still adds noise (caches, memory bandwidth): the load average above says how busy "
           "it was, and ratios between engines measured in the same run are steadier than absolute times.",
           "- The exact reference runs in each invocation: rattle's predictive mode for collision counts, "
           "rattle's hybrid mode at dt <= 1/240 for sensor events (exact like the predictive mode, whose "
           "collisions are the other reference: both find sensor events along the paths the bodies took).",
           "- Box2D moves no body more than 2 units per step (b2_maxTranslation, compiled in), so faster "
           "bodies are slowed; Debian's Chipmunk is a debug build (runtime assertion checks on). Both are "
           "measured as packaged.",
           "- The `arena` tables are the demo's game (rattle's three modes only, at the game's tick of 1/30 s): "
           "the step time is the game's own measure of the engine step; tunnelled counts projectiles whose "
           "centre crossed a wall, sensor missed the begins the positions show and the engine did not report, "
           "and the contact count error compares with the predictive mode's game from the same seed, which is "
           "a game of its own (the hybrid row shows how far two exact games drift apart).",
           "", "## Targets (issue 4), measured side by side in this run", "",
           targets(rows, scaling_rows, repeat_rows), "",
           "## Targets (issue 24: crowds and piles in bounded time), measured side by side in this run", "",
           "Ratios of engines measured in this run. A row stopped at its wall-clock limit (bench/run_matrix.py) did "
           "not finish: its targets are not met, and its counts cover only the stretch it ran, which depends on "
           "the machine.", "",
           targets_issue24(rows), ""]
    if repeat_rows:
        md += ["### The speed targets' gas, repeated", "",
               "The gas row of the two speed targets (%s disks, packing 0.3, dt 1/60, %s s), run again with "
               "hybrid, Box2D and Chipmunk in turn, once per repeat: one run's ratio moves with the machine, so "
               "the targets above are judged by the median of these. Raw rows: [repeats.csv](repeats.csv)." %
               (repeat_rows[0]["n"], repeat_rows[0]["seconds"]), "",
               repeats_table(repeat_rows), ""]
    for key, title, trs in scene_tables(rows):
        png = os.path.join(figures, key + ".png")
        with tempfile.TemporaryDirectory() as tmp:
            speed_error_figure(key, title, trs, png, tmp)
        md += ["## %s" % title, ""]
        extra = {p for p in (r.get("collapse_time", "") for r in trs) if p}
        if extra:
            md += ["rattle's modes (discrete, hybrid, predictive) and the exact reference ran with --collapse-time "
                   "%s (WorldDef::collapseTime, the TC model), as this row has since the predictive mode and the "
                   "reference reached the event budget with the default (0); they complete with it now, as the "
                   "pile-target rows show (see bench/README.md)." %
                   ", ".join(extra), ""]
        table = bullets_table(trs) if key == "bullets" else arena_table(trs) if key.startswith("arena") else \
            crowd_table(trs) if key.startswith("crowd") else generic_table(trs)
        md += [table, "",
               "![%s](figures/%s.png)" % (title, key), ""]
    if scaling_rows:
        with tempfile.TemporaryDirectory() as tmp:
            hybrid, pred = scaling_figure(scaling_rows, os.path.join(figures, "scaling.png"), tmp)
        md += ["## Scaling", "",
               "Hybrid: mean time of one step of 1/60 s on gas at packing 0.3, after 0.5 s of settling (it should "
               "grow like N). Predictive: the step time divided by the collisions processed in it, on gas at "
               "packing 0.5, with one look at the end of the timed stretch (after untimed looks as long, at least "
               "0.5 s of them) and with a look every 1/60 s (after 0.5 s untimed): the untimed start builds the "
               "grid, predicts every disk once and lets the collision rate settle, a cost of starting and not of collisions, "
               "which at 10^6 disks (under one collision per disk in 0.5 s) would otherwise be most of the "
               "measure. Per collision it should grow like log N; a look costs O(N), as every body is brought up "
               "to the time looked at. The baseline `edmd` is the textbook "
               "event-driven gas written for the bench (bench/engine_edmd.cpp: one event per disk, cell "
               "crossings, a 4-ary heap, nothing else), on the one-look runs: what a gas costs without an "
               "engine's generality. The baseline `edmd-lean` is the same method written for speed alone "
               "(bench/engine_edmd_lean.cpp: one cache line per disk, cells of four fixed slots, pairs sifted "
               "without branches, a calendar queue, the next events' records asked for ahead; equal disks only, "
               "no contacts reported, no round-off guard), up to 10^5 disks: about what a special-purpose code "
               "reaches on this machine. Slopes are least-squares fits of log time against log N.", "",
               "| disks | hybrid ms/step | hybrid ns/disk/step | predictive us/collision (one look) | "
               "predictive us/collision (look every 1/60 s) | baseline edmd us/collision (one look) | "
               "baseline edmd-lean us/collision (one look) |",
               "|---|---|---|---|---|---|---|"]
        ns = sorted({int(num(r, "n")) for r in scaling_rows})
        hd, p1, p2 = dict(hybrid), dict(pred["predictive-one-look"]), dict(pred["predictive-1/60"])
        p3, p4 = dict(pred["edmd-one-look"]), dict(pred["edmd-lean-one-look"])
        for n in ns:
            md.append("| %d | %s | %s | %s | %s | %s | %s |" %
                      (n, fmt(hd.get(n)), fmt(hd[n] * 1e6 / n if n in hd else None), fmt(p1.get(n)),
                       fmt(p2.get(n)), fmt(p3.get(n)), fmt(p4.get(n))))
        md += ["", "Slopes (log-log): hybrid time per step %.2f (1 = linear); predictive time per collision %.2f with "
               "one look, %.2f with a look every 1/60 s (0 = flat; log N grows by a slope of about 0.1 over this "
               "range)." % (fit_slope(hybrid), fit_slope(pred["predictive-one-look"]),
                            fit_slope(pred["predictive-1/60"])), ""]
        # A step stopped by the event budget covered less than its dt: its time per collision still holds,
        # but say so rather than let it pass for a whole look.
        budget = ["%s at %d disks (%s)" % (r["series"], int(num(r, "n")), r["notes"]) for r in scaling_rows
                  if "event budget" in r.get("notes", "")]
        if budget:
            md += ["Runs that reached the world's event budget: " + "; ".join(budget) + ".", ""]
        md += ["![scaling](figures/scaling.png)", ""]
    with open(os.path.join(out_dir, "RESULTS.md"), "w") as f:
        f.write("\n".join(md))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", default=here, help="where results.csv, scaling.csv are and RESULTS.md goes")
    ap.add_argument("--bench", default=os.path.join(here, "..", "build", "bin", "rattle-bench"))
    ap.add_argument("--matrix-seconds", type=float, default=None)
    ap.add_argument("--load", default=None, help="load averages at the start and end, 'A,B'")
    a = ap.parse_args()
    write_report(a.dir, a.bench, a.matrix_seconds, a.load.split(",") if a.load else None)


if __name__ == "__main__":
    main()
