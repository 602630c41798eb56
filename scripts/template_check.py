"""Checks the output of the firmware templates (templates/firmware in Rust,
templates/c-firmware in C) against f64: usage
    template_check.py OUTPUT FLOW_RS RUNS
OUTPUT holds RUNS runs, each starting with a line "<name> on <machine>: ...";
FLOW_RS is templates/firmware/src/flow.rs, whose constants (pixel spread,
hit distances, bounces, texture size and level colours) both templates use.
Per run: hits per depth 2^d, each depth's lod within the table lod's bound
2^-8 of log2(Pl / Pb) in f64, its texel within the ACCURATE filter's 0.5625
LSB of the f64 trilinear blend at that lod, the ray stack's high-water mark
B + 1 (one waiting sibling per depth 1 .. B-1, plus the two newest) with
nothing dropped; every run's lines after its first equal.
Run by scripts/templates and scripts/c-abi."""
import math, re, sys
out, flow, want_runs = open(sys.argv[1]).read(), open(sys.argv[2]).read(), int(sys.argv[3])

def const(name):
    m = re.search(rf"const {name}: [^=]+= ([^;]+);", flow, re.S)
    if not m:
        sys.exit(f"FAIL: no const {name} in {sys.argv[2]}")
    return m.group(1)

spread = round(float(re.search(r'"([0-9.]+)"', const("SPREAD")).group(1)) * 2**30) / 2**30
first, nxt, bounces = int(const("FIRST_T")), int(const("NEXT_T")), int(const("BOUNCES"))
size, levels = int(const("SIZE")), int(const("LEVELS"))
colours = [int(c.replace("_", ""), 16) for c in re.findall(r"0x[0-9A-Fa-f_]+", const("LEVEL_RGBA"))]
# The triangle: a right triangle of legs 1 mapped onto the whole texture once.
area, texels = 0.5, 0.5 * size * size
pb = math.sqrt(area / texels) / spread

runs = re.split(r"^(?=[a-z-]*firmware on )", out, flags=re.M)[1:]
if len(runs) != want_runs:
    sys.exit(f"FAIL: expected {want_runs} runs in the output, found {len(runs)}")
bodies = []
for run in runs:
    name = run.splitlines()[0].split(":")[0]
    rows = re.findall(r"^depth +(\d+): +(\d+) hits, lod [-0-9.]+ \(bits (-?\d+)\), rgba 0x([0-9a-f]{8})$", run, re.M)
    if len(rows) != bounces + 1:
        sys.exit(f"FAIL: {name}: {len(rows)} depth lines, expected {bounces + 1}")
    worst_lod = worst_lsb = 0.0
    for d, hits, bits, rgba in rows:
        d, hits, bits, rgba = int(d), int(hits), int(bits), int(rgba, 16)
        if hits != 2**d:
            sys.exit(f"FAIL: {name}: depth {d}: {hits} hits, expected 2^{d}")
        want = math.log2((first + d * nxt) / pb)
        err = abs(bits / 256 - want)
        worst_lod = max(worst_lod, err)
        if err > 2**-8:
            sys.exit(f"FAIL: {name}: depth {d}: lod {bits / 256} vs f64 {want:.5f} (bound 2^-8)")
        # Trilinear between the uniform levels at the firmware's lod.
        lod = min(max(bits / 256, 0.0), levels - 1)
        lo = min(int(lod), levels - 1)
        hi, f = min(lo + 1, levels - 1), lod - lo
        for ch in range(4):
            c0, c1 = colours[lo] >> 8 * ch & 255, colours[hi] >> 8 * ch & 255
            exact = c0 * (1 - f) + c1 * f
            got = rgba >> 8 * ch & 255
            worst_lsb = max(worst_lsb, abs(got - exact))
            if abs(got - exact) > 0.5625:
                sys.exit(f"FAIL: {name}: depth {d}: channel {ch} = {got}, f64 trilinear {exact:.3f} (bound 0.5625 LSB)")
    m = re.search(r"^ray stack: at most (\d+) of (\d+) entries, (\d+) continuations dropped; (\d+) hits$", run, re.M)
    if not m:
        sys.exit(f"FAIL: {name}: no ray-stack line")
    most, cap, dropped, hits = map(int, m.groups())
    # Depth-first, two continuations per hit below the bounce limit: one
    # waiting sibling per depth 1 .. B-1 plus the two newest = B + 1.
    if (most, cap, dropped, hits) != (bounces + 1, bounces + 1, 0, 2 ** (bounces + 1) - 1):
        sys.exit(f"FAIL: {name}: ray stack {most}/{cap}, {dropped} dropped, {hits} hits")
    print(f"templates: {name}: {len(rows)} depths, lod within {worst_lod:.5f} levels of f64, "
          f"texels within {worst_lsb:.3f} LSB, ray stack {most} of {cap}")
    bodies.append(run.split("\n", 1)[1])
if any(b != bodies[0] for b in bodies):
    sys.exit("FAIL: the runs print different results")
print(f"templates: the {len(bodies)} runs print the same results")
