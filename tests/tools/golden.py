#!/usr/bin/env python3
"""golden.py -- the numbers of a run, to the bit, against a stored golden file.

    golden.py extract RUN_DIR KIND            print the run's golden record
    golden.py compare RUN_DIR KIND GOLDEN     exit 1 (and say what differs)
                                              unless the record equals GOLDEN
    golden.py write RUN_DIR KIND GOLDEN       store the record as GOLDEN

KIND is "run" (a folder of `mpgm run`) or "material" (a folder holding the
out.csv of `mpgm material`). The record holds what a refactor must not
change and nothing that may change between two runs of the same binary:

- from summary.json: status, failed_step, method, shape, solver, effects,
  counts (not clock_reads, which counts timer calls), metrics, probes
  (of a run that did not complete: metrics_at_stop, probes_at_stop),
  newton_last_step (residual history of the last step) and the step cuts
  (step, time, size and error code; not the message's wording);
- the SHA-256 of probes.csv, of steps.csv without its timing columns
  (names ending in "_s"), of the last points and mesh VTK files (every
  point's position, displacement, velocity, stress, ... as doubles), of
  every Matrix Market file (comment lines, which name the scene's path, left
  out), and of a material driver's CSV; and the number of VTK files.

Numbers are compared exactly: JSON keeps the 17 significant digits mpgm
writes, and Python's float repr writes back the same double.
"""
import hashlib
import json
import os
import sys


def sha(data):
    return hashlib.sha256(data).hexdigest()


def csv_without_timing(path):
    lines = open(path, "rb").read().decode().splitlines()
    if not lines:
        return ""
    head = lines[0].split(",")
    keep = [i for i, h in enumerate(head) if not h.endswith("_s")]
    return "\n".join(",".join(r.split(",")[i] for i in keep) for r in lines)


def mtx_without_comments(path):
    out = []
    for k, line in enumerate(open(path, "rb").read().splitlines()):
        if k == 0 or not line.startswith(b"%"):
            out.append(line)
    return b"\n".join(out)


def last_file(folder, prefix):
    if not os.path.isdir(folder):
        return None
    names = sorted(n for n in os.listdir(folder) if n.startswith(prefix) and n.endswith(".vtk"))
    return names[-1] if names else None


def run_record(d):
    s = json.load(open(os.path.join(d, "summary.json")))
    # a run that did not complete has its metrics and probes as
    # "metrics_at_stop" / "probes_at_stop", with the time and step they were
    # taken at; the record keeps the numbers under the blocks' plain names
    for k in ("metrics", "probes"):
        if k + "_at_stop" in s:
            block = s[k + "_at_stop"]
            if k == "metrics":
                s[k] = {m: v for m, v in block.items() if m not in ("t", "step")}
            else:
                s[k] = {n: {f: v for f, v in q.items() if f not in ("t", "step")} for n, q in block.items()}
    rec = {k: s[k] for k in ("status", "failed_step", "method", "shape", "solver", "effects",
                             "counts", "metrics", "probes", "newton_last_step") if k in s}
    rec["counts"] = {k: v for k, v in rec["counts"].items() if k != "clock_reads"}
    rec["step_cuts"] = [{k: c[k] for k in ("step", "t", "dt", "code")} for c in s.get("step_cuts", [])]
    files = {"probes.csv": sha(open(os.path.join(d, "probes.csv"), "rb").read()),
             "steps.csv (no timings)": sha(csv_without_timing(os.path.join(d, "steps.csv")).encode())}
    vtk = os.path.join(d, "vtk")
    for prefix in ("points_", "mesh_"):
        name = last_file(vtk, prefix)
        if name:
            files["vtk/" + name] = sha(open(os.path.join(vtk, name), "rb").read())
    rec["vtk_files"] = len(os.listdir(vtk)) if os.path.isdir(vtk) else 0
    mdir = os.path.join(d, "matrices")
    if os.path.isdir(mdir):
        for name in sorted(os.listdir(mdir)):
            if name.endswith(".mtx"):
                files["matrices/" + name] = sha(mtx_without_comments(os.path.join(mdir, name)))
    rec["files"] = files
    return rec


def material_record(d):
    path = os.path.join(d, "out.csv")
    lines = open(path).read().splitlines()
    return {"rows": len(lines) - 1, "last_row": lines[-1], "files": {"out.csv": sha(open(path, "rb").read())}}


def record(d, kind):
    return run_record(d) if kind == "run" else material_record(d)


def flatten(x, path="", out=None):
    out = {} if out is None else out
    if isinstance(x, dict):
        for k, v in x.items():
            flatten(v, f"{path}.{k}" if path else k, out)
    elif isinstance(x, list):
        for i, v in enumerate(x):
            flatten(v, f"{path}[{i}]", out)
    else:
        out[path] = x
    return out


def main(argv):
    if len(argv) < 3 or argv[0] not in ("extract", "compare", "write"):
        print(__doc__, file=sys.stderr)
        return 2
    rec = record(argv[1], argv[2])
    if argv[0] == "extract":
        print(json.dumps(rec, indent=1, sort_keys=True))
        return 0
    if argv[0] == "write":
        with open(argv[3], "w") as f:
            f.write(json.dumps(rec, indent=1, sort_keys=True) + "\n")
        return 0
    gold = json.load(open(argv[3]))
    if rec == gold:
        return 0
    a, b = flatten(gold), flatten(rec)
    for k in sorted(set(a) | set(b)):
        if a.get(k, "(absent)") != b.get(k, "(absent)"):
            print(f"  {k}: golden {a.get(k, '(absent)')!r}, now {b.get(k, '(absent)')!r}")
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
