#!/usr/bin/python3
"""bench/compact.py -- a benchmark part's compact section and its plot.

docs/benchmarks.md shows each part as one table, one plot and one line of
conditions; the full section a benchmark script writes (every table, the
time splits, the experiments) is kept in bench/notes/PART.md, and the compact
section is cut from it here, by the rules of SPEC below, so that what the
report shows is always a selection of what was measured, never a new number.
bench/report calls this for each part it assembles from a new result.

  compact.py section PART FULL.md CONDITIONS   the compact section on stdout
  compact.py plot PART FULL.md OUT.png         draw the part's plot (gnuplot)
  compact.py image PART                        where the part's plot is, from docs/
"""
import os, re, subprocess, sys, tempfile

# For each part: its table (the index of the table in the full section, the
# rows kept, the columns kept and status cells cut at their first ':'), a
# line saying what it measures, and its plot: an image the benchmark draws
# itself ('image'), or lines or bars drawn here from one of the section's
# tables. A part without a rule here is shown as written (`pictures`).
SPEC = {
    "cantilever_convergence": dict(
        what="Static cantilever, tip deflection against h (the paper's Fig. 7): observed orders beside the paper's; "
             "the study `cases/studies/cantilever_convergence.json`.",
        table=1, image="img/cantilever_convergence_error_h.png"),
    "cantilever_split": dict(
        what="Static cantilever, UL-FEM Q4, h = 0.03125 m: time per Newton iteration by phase, OpenBLAS against the "
             "reference BLAS (aim of issue 2: the rest costs less than factor + solve).",
        table=0,
        plot=dict(kind="bars", table=0, label="phase [ms per Newton iteration]", values=["OpenBLAS", "reference BLAS"],
                  rows=lambda r: not r["phase [ms per Newton iteration]"].startswith(("**", "whole")),
                  ylabel="time per Newton iteration [ms]")),
    "rolling_disk": dict(
        what="Rolling disk, MPM, h = 0.01 m over 1 s, contact at the rim points: error (eq 67) and wall time against "
             "the paper's Table 1 (Intel i7-4790); aim of issue 3: 10x faster at equal or better error.",
        table=0, cols=["dt [s]", "status", "steps", "step cuts", "s error", "error [m]", "paper error [m]",
                       "Newton its/step", "wall [s]", "paper wall [s]", "speed-up"],
        plot=dict(kind="lines", table=0, x="dt [s]", ys=["error [m]", "paper error [m]", "wall [s]", "paper wall [s]"],
                  logx=True, logy=True, xlabel="dt [s]", ylabel="error (67) [m], wall time [s]")),
    "rolling_disk_table1": dict(
        what="Rolling disk, the paper's Table 1: every method at h = 0.01 m over 1 s; error (67) [m] and wall [s], "
             "in brackets the paper's.",
        table=0, image="img/rolling_disk_table1_error_time.png"),
    "gmm_lme_radius": dict(
        what="GMM-LME on the rolling disk of Table 1 (h = 0.01 m, dt = 0.004 s, one thread): the paper's fixed "
             "cloud radius against mpgm's cut; error (67), in brackets the paper's.",
        table=0, cols=["gamma", "radius", "status", "steps", "cuts", "K nnz", "error (67) [m]", "wall [s]",
                       "assembly [s]", "solver [s]"], trim=["status"],
        plot=dict(kind="lines", table=0, x="K nnz", ys=["wall [s]"], group="gamma",
                  xlabel="entries of the tangent K", ylabel="wall time [s]", key="gamma ")),
    "rolling_disk_gmm": dict(
        what="Rolling disk with GMM (`cases/rolling_disk_gmm.json`), h = 0.01 m over 1 s: error (67), wall time and "
             "its split.",
        table=0, cols=["run", "status", "steps", "cuts", "s error", "error [m]", "Newton its/step", "wall [s]",
                       "search+shape [s]", "assembly+material [s]", "analyse [s]", "factor+solve [s]"],
        plot=dict(kind="bars", table=0, label="run",
                  values=["search+shape [s]", "assembly+material [s]", "analyse [s]", "factor+solve [s]"],
                  ylabel="time of the run [s]")),
    "gmm_sweep": dict(
        what="GMM to the end on the column collapse (`cases/studies/gmm_sweep_column.json`, 2 s): every shape at "
             "h = 0.1 and 0.05 m, nodes moved by their coefficients or by the field; the rolling-disk half of the "
             "sweep (16 of 16 complete) is in the details.",
        table=1, cols=["shape", "h [m]", "status", "steps", "step cuts", "runout [m]", "height [m]", "wall [s]"],
        trim=["status"],
        plot=dict(kind="bars", table=1, label="shape", series="h [m]", values=["runout [m]"],
                  rows=lambda r: r["status"] == "completed", ylabel="runout at 2 s [m] (completed runs)",
                  key="h = ", yrange="4:4.8")),
    "explicit": dict(
        what="Dyka's bar (`cases/studies/dyka_bar.json`): velocity RMS (eq 44) [m/s] at the end, in brackets at 1e-5 s, "
             "for three schemes and four shapes over the paper's 7 meshes; the speed of explicit MPM, the colliding "
             "discs, the rigid block and the cantilever against implicit are in the details.",
        table=1, image="img/dyka_bar_error_h.png"),
    "mms": dict(
        what="Manufactured solutions (seed 004), the axis-aligned vibration at A = 0.1 m on the finest mesh "
             "(h = 1/512 m): RMS errors of eq 47 and the orders from the mesh before; every mesh, the ring and "
             "the vortex are in the details.",
        table=0, rows=lambda r: r["shape, per cell, A [m]"].endswith(", 0.1") and r["h [m]"] == "0.001953",
        image="img/mms_vibration_error_h.png"),
    "kdtree": dict(
        what="mpgm's kd-tree against nanoflann and brute force, n random points in the unit square: build times "
             "(the table) and radius queries in random order (the plot).",
        table=0, cols=["n", "build ours [ms]", "build nanoflann [ms]", "ours/nanoflann", "refit ours after a move [ms]",
                       "tree memory [MB]"],
        plot=dict(kind="lines", table=1, x="n", ys=["ours [µs/query]", "nanoflann [µs/query]", "brute force [µs/query]"],
                  rows=lambda r: r["query"] == "radius" and r["query order"] == "random", logx=True, logy=True,
                  xlabel="points n", ylabel="time per radius query [µs]")),
    "shapefn_cost": dict(
        what="Cost of one evaluation of N and grad N at a point, by the size of its cloud (one thread).",
        table=0,
        plot=dict(kind="lines", table=0, x="nodes",
                  ys=["LME cold [us]", "LME warm [us]", "MLS linear [us]", "MLS quadratic [us]"],
                  xlabel="nodes in the cloud", ylabel="time per evaluation [µs]")),
    "column_collapse": dict(
        what="Soil column collapse (`cases/column_collapse.json`, `cases/column_collapse_gmm.json`), Mohr-Coulomb, "
             "2 s: runout and height at 2 s (initially 4 m and 2 m), step cuts, wall time; the picture: MPM on mesh 1 "
             "coloured by eps_p at the paper's instants.",
        table=0, cols=["run", "status", "points", "dt [s]", "steps", "cuts", "runout [m]", "height [m]", "eps_p max",
                       "Newton its/step", "wall [s]"], trim=["status"],
        image="img/column_collapse_mpm_1.png"),
    "solvers": dict(
        what="Sparse linear solvers on the first Newton system of the cantilever, rolling disk and column collapse: "
             "the fastest direct solver against the fastest Krylov solver (total = analyse + factor + solve); every "
             "backend on every system is in the details.",
        table=1,
        plot=dict(kind="bars", table=1, label="case", values=["total [ms]", "total [ms] #2"],
                  titles=["fastest direct", "fastest Krylov"], logy=True, ylabel="analyse + factor + solve [ms]")),
    "cost_growth": dict(
        what="Column collapse (MPM), 10 steps at h = 0.1 to 0.0125 m, PETSc GMRES + ILU(0) with forcing (the case's "
             "solver): time per Newton iteration by phase against the equations; UMFPACK in the details.",
        table=1, cols=["h [m]", "equations", "Newton its", "Krylov its", "assembly [ms/it]", "material [ms/it]",
                       "shape + search [ms/it]", "linear solver [ms/it]", "all phases [ms/it]"],
        plot=dict(kind="lines", table=1, x="equations",
                  ys=["assembly [ms/it]", "material [ms/it]", "linear solver [ms/it]", "all phases [ms/it]"],
                  logx=True, logy=True, xlabel="equations", ylabel="time per Newton iteration [ms]")),
    "three_d": dict(
        what="3-D (issue 53): each case as a slab with rollers on z against its plane-strain run on the same mesh "
             "in x and y (the table); the free cantilever's convergence, the free column collapse, the implicit cost "
             "against equations with GAMG, the explicit speed and geomechanics/mpm are in the details.",
        table=0, cols=["case", "metric", "plane strain", "slab", "rel. difference"],
        image="img/column_collapse_3d_free_fe.png"),
    "processes": dict(
        what="Strong scaling on this machine (issue 54): the 3-D explicit elastic column of 10^6 points on one "
             "process, on two (mpiexec -n 2), on one with two threads, and as two separate runs at once (what two "
             "processes of the machine give at most); a step's time apart from the set-up.",
        table=0,
        cols=["configuration", "processes x threads", "points on the busiest process", "step [ms]",
              "speed-up per step", "set-up [s]", "run of 50 steps [s]", "speed-up of the run"],
        plot=dict(kind="bars", table=0, label="configuration", values=["speed-up per step", "speed-up of the run"],
                  short=True, ylabel="against one process, one thread")),
    "timers": dict(
        what="What mpgm's timers cost: clock reads of a run times the cost of one read, against its wall time "
             "(aim of issue 6: under 1 %).",
        table=0,
        plot=dict(kind="bars", table=0, label="run", values=["share of the run"], short=True,
                  ylabel="timers' share of the run [%]")),
    "fuzz": dict(
        what="libFuzzer on the scene reader and the checkpoint reader (`scripts/fuzz`): executions, findings, "
             "coverage (the plot: edges covered in the files that read scenes).",
        table=0,
        plot=dict(kind="bars", table=1, label="file", values=["share"], ylabel="edges covered [%]",
                  yrange="0:100")),
    "compare_binaries": dict(
        what="Two binaries in one sitting, alternating (`bench/compare_binaries`): before and after the "
             "dimension rewrite of issue 53 (the 2-D path must stay within 3 %).",
        table=0,
        plot=dict(kind="bars", table=0, label="run", values=["A median [s]", "B median [s]"], short=True,
                  titles=["A (1ef250e, before)", "B (after)"], ylabel="median wall time [s]")),
    "output_formats": dict(
        what="Output formats on a run of 10^6 points or more: file size and write time of VTK XML (.vtu), "
             "XDMF + HDF5 and legacy VTK (issue 52, item 2).",
        table=0,
        plot=dict(kind="bars", table=0, label="format", values=["size per frame [MB]", "write time per frame [s]"],
                  titles=["size of a frame [MB]", "write time of a frame [s]"], logy=True,
                  ylabel="MB, s (log scale)")),
}

ROW = re.compile(r"^\|.*\|\s*$")
SEP = re.compile(r"^\|[-:| ]+\|\s*$")


def cells(line):
    """The cells of a markdown table row (a '|' escaped as '\\|' stays in its cell)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]


def tables(text):
    """Every table of a section: (first line, last line + 1, header, rows as dicts)."""
    lines, out, i = text.split("\n"), [], 0
    while i + 1 < len(lines):
        if ROW.match(lines[i]) and SEP.match(lines[i + 1]):
            head, seen = [], {}
            for h in cells(lines[i]):     # a repeated header is told apart as 'NAME #2'
                seen[h] = seen.get(h, 0) + 1
                head.append(h if seen[h] == 1 else f"{h} #{seen[h]}")
            j, rows = i + 2, []
            while j < len(lines) and ROW.match(lines[j]):
                c = cells(lines[j])
                rows.append(dict(zip(head, c + [""] * (len(head) - len(c)))))
                j += 1
            out.append((i, j, head, rows))
            i = j
        else:
            i += 1
    return out


def number(cell):
    """The first number of a cell ('**0.233** (2.34)' -> 0.233, '1 297 064' -> 1297064, '69 %' -> 69)."""
    s = cell.replace("**", "").replace("\u202f", "").replace(",", "")
    s = re.sub(r"(?<=\d) (?=\d{3}\b)", "", s.split("(")[0])
    m = re.search(r"[-+]?\d*\.?\d+(?:e[-+]?\d+)?", s)
    return float(m.group(0)) if m else None


def q(s):
    """S as a gnuplot string."""
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def title_of(text, part):
    for line in text.split("\n"):
        if line.startswith("#"):
            return "### " + line.lstrip("#").strip()
    return f"### {part}"


def section(part, text, conditions):
    """The compact section of PART cut from its full section TEXT."""
    spec = SPEC.get(part)
    if spec is None:
        return text.strip() + "\n"
    ts = tables(text)
    out = [title_of(text, part), "", spec["what"], "", "Conditions: " + conditions.strip(), ""]
    if ts:
        _, _, head, rows = ts[min(spec.get("table", 0), len(ts) - 1)]
        keep = [h for h in spec.get("cols", head) if h in head]
        rows = [r for r in rows if spec.get("rows", lambda r: True)(r)]
        out.append("| " + " | ".join(h.split(" #")[0] for h in keep) + " |")
        out.append("|" + "|".join("---" if any(number(r[h]) is None for r in rows if r[h]) else "---:"
                                  for h in keep) + "|")
        for r in rows:
            vals = [r[h].split(":")[0] if h in spec.get("trim", []) else r[h] for h in keep]
            out.append("| " + " | ".join(vals) + " |")
        out.append("")
    img = image(part)
    if img:
        out.append(f"![{title_of(text, part)[4:]}]({img})")
        out.append("")
    return "\n".join(out)


def image(part):
    spec = SPEC.get(part) or {}
    if "image" in spec:
        return spec["image"]
    return f"img/bench_{part}.png" if "plot" in spec else None


def plot(part, text, png):
    """Draw PART's plot from its full section into PNG with gnuplot; False if there is nothing to draw."""
    p = (SPEC.get(part) or {}).get("plot")
    if p is None:
        return False
    ts = tables(text)
    if p["table"] >= len(ts):
        return False
    _, _, head, rows = ts[p["table"]]
    rows = [r for r in rows if p.get("rows", lambda r: True)(r)]
    label = head[p["label"]] if isinstance(p.get("label"), int) else p.get("label")
    values = p.get("values")
    gp = ["set terminal pngcairo size 900,560 enhanced font ',11'", f"set output '{png}'",
          "set grid", "set key outside top center horizontal", "set offsets graph 0.03, graph 0.03", f"set ylabel {q(p.get('ylabel', ''))}"]
    if p.get("logy"):
        gp.append("set logscale y")
    if p.get("yrange"):
        gp.append(f"set yrange [{p['yrange']}]")
    data = []
    if p["kind"] == "lines":
        gp.append(f"set xlabel {q(p.get('xlabel', p['x']))}")
        if p.get("logx"):
            gp.append("set logscale x")
        gp.append("set autoscale xfix")
        groups = {}
        for r in rows:
            groups.setdefault(r[p["group"]] if p.get("group") else "", []).append(r)
        series = []
        for g, rs in groups.items():
            for y in p["ys"]:
                pts = [(number(r[p["x"]]), number(r[y])) for r in rs]
                pts = sorted((x, v) for x, v in pts if x is not None and v is not None)
                if not pts:
                    continue
                data.append("\n".join(f"{x:.10g} {v:.10g}" for x, v in pts))
                name = (p.get("key", "") + g) if g else y
                series.append(f"'-' using 1:2 with linespoints lw 2 pt 7 title {q(name)}")
        if not series:
            return False
        gp.append("plot " + ", ".join(series))
    else:
        labels = []
        if p.get("series"):   # one group of bars per label, one bar per value of the series column
            keys = list(dict.fromkeys(r[p["series"]] for r in rows))
            table = {}
            for r in rows:
                table.setdefault(r[label], {})[r[p["series"]]] = number(r[values[0]])
            labels = list(table)
            cols = [[table[l].get(k) for l in labels] for k in keys]
            names = [p.get("key", "") + k for k in keys]
        else:
            labels = [r[label] for r in rows]
            cols = [[number(r[v]) for r in rows] for v in values]
            names = p.get("titles", [v.split(" #")[0] for v in values])
        if not labels or not any(v is not None for c in cols for v in c):
            return False
        if p.get("short"):
            labels = [", ".join(l.split("(")[0].split(", ")[:2]).strip() for l in labels]
        labels = [l.replace("`", "").replace('"', "'") for l in labels]
        long = sum(map(len, labels)) > 70
        if not p.get("logy") and not p.get("yrange"):
            gp.append("set yrange [0:*]")   # bars start at zero
        gp += ["set style data histograms", "set style histogram clustered gap 1", "set style fill solid 0.8 border -1",
               "set boxwidth 0.9", "set xtics rotate by 30 right noenhanced" if long else "set xtics noenhanced",
               f"set bmargin {min(3 + int(0.32 * max(map(len, labels))), 16)}" if long else "set bmargin 3", "set lmargin 12"]
        block = "\n".join(f"\"{l}\" " + " ".join("NaN" if c[i] is None else f"{c[i]:.10g}" for c in cols)
                          for i, l in enumerate(labels))
        gp.append("plot " + ", ".join(f"'-' using {k + 2}:xtic(1) title {q(n)}" for k, n in enumerate(names)))
        data = [block] * len(cols)
    return gnuplot("\n".join(gp) + "\n" + "".join(d + "\ne\n" for d in data), part)


def gnuplot(script, what):
    """Run a gnuplot SCRIPT (from a temporary file); False, with gnuplot's message, if it failed."""
    with tempfile.NamedTemporaryFile("w", suffix=".gp", delete=False) as f:
        f.write(script)
    try:
        r = subprocess.run(["gnuplot", f.name], capture_output=True, text=True)
    finally:
        os.unlink(f.name)
    if r.returncode != 0:
        sys.stderr.write(f"bench/compact.py: gnuplot failed for {what}:\n{r.stderr}")
        return False
    return True


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "image":
        print(image(sys.argv[2]) or "")
    elif len(sys.argv) == 5 and sys.argv[1] == "section":
        sys.stdout.write(section(sys.argv[2], open(sys.argv[3]).read(), sys.argv[4]))
    elif len(sys.argv) == 5 and sys.argv[1] == "plot":
        sys.exit(0 if plot(sys.argv[2], open(sys.argv[3]).read(), sys.argv[4]) else 1)
    else:
        sys.exit(__doc__)
