#!/usr/bin/env python3
"""doc_defaults.py -- every default that docs/scene-format.md states is the
default `mpgm check` resolves.

    doc_defaults.py MPGM_EXE SOURCE_DIR WORK_DIR

The tables of docs/scene-format.md with a "default" column are read; a
row's key gets its path from the section it stands in (## mesh -> mesh.KEY,
## bodies -> bodies.0.KEY, a material type's parameter table ->
materials.<that type>.KEY, a reference kind's -> reference.KEY, ...).
Minimal scenes (SCENES below: only required keys, plus what makes a
section's defaults appear) are resolved with `mpgm check`; a row is
compared in the first scene whose input lacks the key and whose resolved
scene has it. A default the checker cannot read, or that no scene
resolves, is a failure unless NOT_VALUES lists the text as "not a value"
(required, conditional descriptions): the tables cannot drift from the code
without a test failing. Prints one PASS/FAIL line per row and "N passed, M
failed".
"""
import json
import math
import re
import subprocess
import sys

# texts of the default column that state no value to compare
NOT_VALUES = {"required", "required, ≥ 1", "–", "-", "none", "all defaults", "static, 1 load step",
              "– (required in `geostatic`)", "required with `disk`", "required with `polygon`", "required with `ring`",
              "required (exactly one)", "all", ""}

MATERIALS = {
    "le": {"type": "linear_elastic", "density": 2385.7, "E": 3.1e7, "nu": 0.287},
    "nh": {"type": "neo_hookean", "density": 2385.7, "E": 3.1e7, "nu": 0.287},
    "mc": {"type": "mohr_coulomb", "density": 1850.0, "E": 1.8e6, "nu": 0.3, "c": 5000.0, "phi": 25.0},
}
MESH = {"h": 0.25, "domain": {"min": [0.0, 0.0], "max": [4.0, 2.0]}}
BLOCK = {"material": "nh", "rectangle": {"min": [0.0, 0.0], "max": [2.0, 1.0]}}
SCENES = {
    # FEM, static: the top level, mesh, time, solver, output, a body, a
    # fixed boundary, the materials (small strain for linear_elastic)
    "fem_static": {"mesh": MESH, "kinematics": "small", "materials": MATERIALS,
                   "bodies": [dict(BLOCK, material="le")], "boundaries": [{"x": 0.0, "fix": ["x", "y"]}]},
    "fem_finite": {"mesh": MESH, "materials": {k: v for k, v in MATERIALS.items() if k != "le"},
                   "bodies": [BLOCK], "boundaries": [{"x": 0.0, "fix": ["x", "y"]}]},
    # GMM-MLS on triangles, dynamic: the meshfree shape parameters, the
    # cell-dependent defaults, contact at points, an obstacle, a rolling disk
    "gmm_dynamic": {"method": "gmm", "shape": {"kind": "mls"},
                    "mesh": dict(MESH, cell="tri", domain={"min": [0.0, -0.5], "max": [4.0, 2.0]}),
                    "time": {"analysis": "dynamic", "dt": 0.01, "end": 0.1},
                    "materials": {"nh": MATERIALS["nh"]},
                    "bodies": [{"material": "nh", "disk": {"centre": [1.0, 0.5], "radius": 0.5}}],
                    "boundaries": [{"y": 0.0, "condition": "contact", "enforce": "points"}],
                    "obstacles": [{"x": 3.5, "side": "right"}],
                    "probes": {"c": [1.0, 0.5]},
                    "reference": {"kind": "rolling_disk", "probe": "c"}},
    # GMM-LME and MPM-CPDI: the keys those kinds alone take (gamma,
    # tol_support; grid_functions)
    "gmm_lme": {"method": "gmm", "shape": {"kind": "lme"}, "mesh": MESH, "materials": {"nh": MATERIALS["nh"]},
                "bodies": [BLOCK], "boundaries": [{"x": 0.0, "fix": ["x", "y"]}]},
    "mpm_cpdi": {"method": "mpm", "shape": {"kind": "cpdi"}, "mesh": MESH, "materials": {"nh": MATERIALS["nh"]},
                 "bodies": [BLOCK], "boundaries": [{"y": 0.0, "fix": ["x", "y"]}]},
    # the PETSc backend: its options' default (the string is read only then)
    "fem_petsc": {"mesh": MESH, "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK],
                  "boundaries": [{"x": 0.0, "fix": ["x", "y"]}], "solver": {"linear": "petsc"}},
    # no boundary at all (a free body, dynamic)
    "mpm_free": {"method": "mpm", "mesh": MESH, "time": {"analysis": "dynamic", "dt": 0.01, "end": 0.1},
                 "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK]},
    # MPM: contact at grid nodes (its enforce default)
    "mpm_contact": {"method": "mpm", "mesh": MESH, "materials": {"nh": MATERIALS["nh"]},
                    "bodies": [BLOCK], "boundaries": [{"y": 0.0, "condition": "contact"}]},
    # MPM, explicit: the keys of the explicit schemes
    "mpm_explicit": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "end": 0.01},
                     "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK], "probes": {"c": [1.0, 0.5]},
                     "reference": {"kind": "dyka_bar", "probe": "c", "component": "x", "length": 2.0,
                                   "modulus": 3.1e7, "density": 2385.7, "v0": -1.0}},
    # MPM, explicit with a fixed step: time.allow_unstable_dt
    "mpm_explicit_dt": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "dt": 1e-4,
                                                                "end": 0.01},
                        "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK]},
    # the rigid_block reference's defaults
    "mpm_block": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "end": 0.01},
                  "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK], "probes": {"c": [1.0, 0.5]},
                  "reference": {"kind": "rigid_block", "probe": "c", "height": 1.0, "density": 2385.7,
                                "from": 0.0}},
    # a ring body: its sector's angles
    "mpm_ring": {"method": "mpm", "mesh": MESH, "materials": {"nh": MATERIALS["nh"]},
                 "bodies": [{"material": "nh", "ring": {"centre": [2.0, 1.0], "inner": 0.3, "outer": 0.6}}]},
    # manufactured solutions: the vibration's L, the ring's and the vortex's
    # radii (each on the bodies its solution holds on: the strip 0 <= x <= L,
    # the annulus ri <= R <= ro of its default radii)
    "mpm_mms_vib": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "end": 0.01},
                    "materials": {"nh": MATERIALS["nh"]},
                    "bodies": [{"material": "nh", "rectangle": {"min": [0.0, 0.0], "max": [1.0, 0.5]}}],
                    "manufactured": {"solution": "vibration", "A": 0.01}},
    "mpm_mms_ring": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "end": 0.01},
                     "materials": {"nh": MATERIALS["nh"]},
                     "bodies": [{"material": "nh", "ring": {"centre": [0.0, 0.0], "inner": 0.4, "outer": 0.6,
                                                            "from": 0.0, "to": 90.0}}],
                     "manufactured": {"solution": "ring", "A": 0.01}},
    "mpm_mms_vortex": {"method": "mpm", "mesh": MESH, "time": {"analysis": "explicit", "end": 0.01},
                       "materials": {"nh": MATERIALS["nh"]},
                       "bodies": [{"material": "nh", "ring": {"centre": [0.0, 0.0], "inner": 0.75, "outer": 1.25,
                                                              "from": 0.0, "to": 90.0}}],
                       "manufactured": {"solution": "vortex", "A": 0.01}},
}


def read_tables(path):
    """(path prefix, key text, default text, line) of every table row with a
    default column."""
    rows, prefix, header, owner = [], None, None, None
    sections = {"Top level": "", "mesh": "mesh", "shape": "shape", "time": "time", "solver": "solver",
                "materials": "materials", "bodies": "bodies.0", "boundaries": "boundaries.0",
                "obstacles": "obstacles.0", "reference": "reference", "output": "output",
                "manufactured": "manufactured"}
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        line = line.rstrip("\n")
        m = re.match(r"^## (.*)$", line)
        if m:
            prefix, header, owner = sections.get(m.group(1).strip()), None, None
            continue
        m = re.match(r"^`([a-z_]+)`: ", line) or re.match(r"^\*\*`([a-z_]+)`\*\*: ", line)
        if m:
            owner = m.group(1)
        if not line.startswith("|"):
            header = None
            continue
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
        if header is None:
            header = [c.lower() for c in cells]
            continue
        if set(cells[0]) <= set("-: ") or prefix is None or "default" not in header:
            continue
        rows.append((prefix, owner, cells[0], cells[header.index("default")], n))
    return rows


def keys_of(text):
    """`a`, `b` -> [a, b]; `x` or `y` -> [x, y]; other text -> []."""
    return re.findall(r"`([A-Za-z0-9_.]+)`", text) if text.startswith("`") else []


def full_path(prefix, owner, key):
    if prefix == "materials" and owner in ("linear_elastic", "neo_hookean", "mohr_coulomb"):
        name = {"linear_elastic": "le", "neo_hookean": "nh", "mohr_coulomb": "mc"}[owner]
        return f"materials.{name}.{key}"
    if prefix == "materials":
        return None  # type and density: required of every entry
    return f"{prefix}.{key}" if prefix else key


def lookup(tree, path):
    for part in path.split("."):
        if isinstance(tree, list):
            if not part.isdigit() or int(part) >= len(tree):
                return None, False
            tree = tree[int(part)]
        elif isinstance(tree, dict) and part in tree:
            tree = tree[part]
        else:
            return None, False
    return tree, True


def expected(text, resolved):
    """The value a default text states in a resolved scene; raises
    ValueError when the text is not understood."""
    t = text.strip()
    cell = resolved.get("mesh", {}).get("cell")
    m = re.fullmatch(r"(\S+) \(quad\), (\S+) \(tri\)", t)
    if m:
        return float(m.group(1) if cell == "quad" else m.group(2))
    m = re.fullmatch(r"dynamic: required;(?: explicit: (\S+) \(from `cfl`\);)? static: (\S+) \(unused\)", t)
    if m:
        analysis = resolved.get("time", {}).get("analysis")
        if analysis == "explicit" and m.group(1):
            return float(m.group(1))
        if analysis != "static":
            raise LookupError("required here")
        return float(m.group(2))
    m = re.fullmatch(r'(`"\w+"`); (`"\w+"`) with `shape\.kind` `"cpdi"` on quads', t)
    if m:  # a default that follows the shape kind
        cpdi = resolved.get("shape", {}).get("kind") == "cpdi" and cell == "quad"
        t = m.group(2 if cpdi else 1)
    m = re.fullmatch(r"(\S+); `cpls`: (\S+)", t)
    if m:  # a default that CPLS sets otherwise
        t = m.group(2 if resolved.get("shape", {}).get("kind") == "cpls" else 1)
    m = re.fullmatch(r"`ring`: (\S+); `vortex`: (\S+)", t)
    if m:  # the manufactured ring's and vortex's defaults
        sol = resolved.get("manufactured", {}).get("solution")
        if sol not in ("ring", "vortex"):
            raise LookupError("ring and vortex only")
        t = m.group(1 if sol == "ring" else 2)
    m = re.fullmatch(r'(\S+); `enforce` `"points"`: (\S+)', t)
    if m:  # a default of scenes with a contact at surface points
        pts = any(b.get("enforce") == "points" for b in resolved.get("boundaries", []))
        t = m.group(2 if pts else 1)
    m = re.fullmatch(r"(explicit|dynamic): (.+)", t)
    if m:  # a key of explicit (implicit dynamic) analysis only
        if resolved.get("time", {}).get("analysis") != m.group(1):
            raise LookupError(m.group(1) + " only")
        t = m.group(2)
    m = re.fullmatch(r"(\S+) \(off\)", t)
    if m:
        t = m.group(1)
    h = resolved.get("mesh", {}).get("h")
    m = re.fullmatch(r"([0-9.e+-]+) · `mesh\.h`", t)
    if m:
        return float(m.group(1)) * h
    m = re.fullmatch(r"`mesh\.h` / ([0-9.]+)", t)
    if m:
        return h / float(m.group(1))
    if t.startswith("`") and t.endswith("`"):
        t = t[1:-1].replace("<i>", "0").replace("<scene file stem>", "STEM")
    try:
        return json.loads(t)
    except json.JSONDecodeError:
        raise ValueError(f"cannot read the default '{text}'")


# statements of the page that were wrong (issue 16, item 6) and must not
# come back: (pattern, what the code does)
RETIRED = [
    (r"Dynamic: λ = min\(1, t / `end`\), so in a dynamic run the loads also ramp",
     "dynamic gravity acts in full from t = 0; only prescribed displacements ramp"),
    (r"The initial acceleration\s+is zero", "time.initial_acceleration defaults to equilibrium"),
]


def free_fall(exe, work):
    """What the page says of dynamic gravity, run: a free block under
    gravity falls g t^2 / 2 (in full from t = 0, from the equilibrium
    initial acceleration), not g t^3 / (6 end) (a ramp)."""
    scene = {"method": "fem", "mesh": MESH, "time": {"analysis": "dynamic", "dt": 0.01, "end": 0.1},
             "materials": {"nh": MATERIALS["nh"]}, "bodies": [BLOCK], "gravity": [0.0, -9.81],
             "probes": {"c": [1.0, 0.5]}, "output": {"vtk": "none"}}
    path = f"{work}/free_fall.json"
    with open(path, "w") as f:
        json.dump(scene, f)
    out = subprocess.run([exe, "run", path, "--quiet", "--out", f"{work}/free_fall"], capture_output=True, text=True)
    if out.returncode != 0:
        return False, out.stderr.strip()
    uy = json.load(open(f"{work}/free_fall/summary.json"))["metrics"]["c_uy"]
    want = -0.5 * 9.81 * 0.1 ** 2
    return abs(uy - want) <= 1e-9 * abs(want), f"uy(0.1 s) = {uy:.12g} m, g t^2 / 2 = {want:.12g} m"


def same(a, b):
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return a == b or abs(a - b) <= 1e-12 * max(abs(a), abs(b))
    return a == b


def main(exe, src, work):
    resolved = {}
    for name, scene in SCENES.items():
        path = f"{work}/{name}.json"
        with open(path, "w") as f:
            json.dump(scene, f)
        out = subprocess.run([exe, "check", path], capture_output=True, text=True)
        if out.returncode != 0:
            print(f"FAIL: scene {name} does not load: {out.stderr.strip()}")
            return 1
        text = out.stdout[:out.stdout.index("\neffects:")]
        resolved[name] = json.loads(text.replace("results/" + name, "results/STEM"))
    npass = nfail = nskip = 0
    for prefix, owner, keytext, default, line in read_tables(f"{src}/docs/scene-format.md"):
        keys = keys_of(keytext)
        if default in NOT_VALUES or not keys:
            nskip += 1
            continue
        for key in keys:
            path = full_path(prefix, owner, key)
            if path is None:
                continue
            where, msg = None, None
            for name, scene in SCENES.items():
                _, given = lookup(scene, path)
                value, found = lookup(resolved[name], path)
                if not given and not found and default in ("`[]`", "`{}`"):
                    where = name  # an absent list is an empty one: the resolved scene leaves it out
                    print(f"PASS: {path} (line {line}): documented default {default}, absent from the "
                          f"resolved scene (scene {name})")
                    npass += 1
                    break
                if given or not found:
                    continue
                try:
                    want = expected(default, resolved[name])
                except LookupError:
                    continue
                except ValueError as e:
                    msg = str(e)
                    break
                where = name
                ok = same(value, want)
                print(("PASS" if ok else "FAIL") + f": {path} (line {line}): documented default {default}, "
                      f"resolved {json.dumps(value)} (scene {name})")
                npass += ok
                nfail += not ok
                break
            if where is None:
                print(f"FAIL: {path} (line {line}): default {default}: {msg or 'no test scene resolves it'}")
                nfail += 1
    page = open(f"{src}/docs/scene-format.md", encoding="utf-8").read()
    for pattern, truth in RETIRED:
        ok = re.search(pattern, page) is None
        print(("PASS" if ok else "FAIL") + f": the page does not say /{pattern}/ ({truth})")
        npass += ok
        nfail += not ok
    ok, what = free_fall(exe, work)
    print(("PASS" if ok else "FAIL") + f": dynamic gravity in full from t = 0, as the page says: {what}")
    npass += ok
    nfail += not ok
    print(f"({nskip} rows state no value: required, or described in words)")
    print(f"{npass} passed, {nfail} failed")
    return 1 if nfail else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
