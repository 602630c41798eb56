#!/usr/bin/env python3
"""The CI time budget (docs/ci-budget.md), run by scripts/ci-budget.

  ci_budget.py sample PID OUT
      every half second until PID ends, one line to OUT: the time
      (centiseconds since the epoch), the CPU ticks of PID's process tree so
      far (utime + stime + cutime + cstime of every live process in it: a
      process that ended is in its parent's cutime once reaped), and the
      number of its threads that are runnable (state R).
  ci_budget.py write --steps TSV --samples FILE --meta FILE --out PAGE
      the page from the step table of scripts/test-all (RAYMIP_STEP_TIMES)
      and those samples.

The projection to an idle machine: in each sample interval the tree used C
CPU-seconds with R threads runnable; on an idle machine with N CPUs those
C seconds take C / min(R, N) wall seconds (at least one thread ran), and an
interval with no CPU used (downloads, sleeps) takes its own length.
"""
import os
import sys
import time

from mdblock import page_head

HZ = os.sysconf("SC_CLK_TCK")


def stat_fields(pid):
    with open(f"/proc/{pid}/stat") as f:
        s = f.read()
    return s[s.rindex(")") + 2:].split()


def label(pid, comm):
    """What a process is, for the per-program table: `rustc CRATE`
    (its --crate-name), the script a python3 or bash runs, else its
    command name."""
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            argv = f.read().decode(errors="replace").split("\0")
    except OSError:
        return comm
    name = os.path.basename(argv[0]) if argv and argv[0] else comm
    if name.startswith("rustc") or name in ("clippy-driver", "rustdoc"):
        if "--crate-name" in argv[:-1]:
            return f"{name} {argv[argv.index('--crate-name') + 1]}"
    if name.startswith(("python", "bash", "sh")) and len(argv) > 1:
        if argv[1] == "-c":
            return f"{name} -c"
        scripts = [a for a in argv[1:] if a.endswith(".py") or "scripts/" in a]
        if scripts:
            return f"{name} {os.path.basename(scripts[0])}"
    return name or comm


def tree_sample(root, procs=None):
    """CPU ticks of root's process tree and its runnable threads; with
    `procs` (a dict), also each process's own ticks: procs[pid] =
    [label, ticks, first seen (centiseconds)]."""
    parent = {}
    fields = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            f = stat_fields(d)
        except OSError:
            continue
        parent[int(d)] = int(f[1])
        fields[int(d)] = f
    tree = set()
    for pid in parent:
        p, seen = pid, 0
        while p > 1 and seen < 64:
            if p == root:
                tree.add(pid)
                break
            p = parent.get(p, 0)
            seen += 1
    ticks = 0
    runnable = 0
    now = int(time.time() * 100)
    for pid in tree:
        f = fields[pid]
        ticks += int(f[11]) + int(f[12]) + int(f[13]) + int(f[14])
        if procs is not None:
            own = int(f[11]) + int(f[12])
            if pid not in procs:
                try:
                    with open(f"/proc/{pid}/stat") as sf:
                        st = sf.read()
                    comm = st[st.index("(") + 1:st.rindex(")")]
                except OSError:
                    comm = "?"
                procs[pid] = [label(pid, comm), own, now]
            procs[pid][1] = max(procs[pid][1], own)
        try:
            tasks = os.listdir(f"/proc/{pid}/task")
        except OSError:
            continue
        for t in tasks:
            try:
                if stat_fields(f"{pid}/task/{t}")[0] == "R":
                    runnable += 1
            except (OSError, ValueError):
                pass
    return ticks, runnable


def write_procs(procs, path):
    with open(path + ".tmp", "w") as o:
        for pid, (lab, ticks, first) in sorted(procs.items()):
            o.write(f"{pid}\t{first}\t{ticks * 100 // HZ}\t{lab}\n")
    os.replace(path + ".tmp", path)


def sample(root, out):
    """Every half second until ROOT exits: a line `time ticks runnable` of
    its tree to OUT; each process's own CPU (the last value seen: a
    process's final half second, and one shorter than that, are missed) to
    OUT.procs, `pid first-seen centiseconds label`."""
    root = int(root)
    procs = {}
    last_write = time.time()
    with open(out, "w") as o:
        while os.path.exists(f"/proc/{root}"):
            t = time.time()
            ticks, runnable = tree_sample(root, procs)
            o.write(f"{int(t * 100)} {ticks} {runnable}\n")
            o.flush()
            if t - last_write > 30:
                write_procs(procs, out + ".procs")
                last_write = t
            time.sleep(max(0.0, 0.5 - (time.time() - t)))
    write_procs(procs, out + ".procs")


def read_steps(path):
    rows = []
    for line in open(path):
        kind, start, wall, cpu, name = line.rstrip("\n").split("\t", 4)
        rows.append(dict(kind=kind, start=int(start), wall=int(wall), cpu=int(cpu), name=name))
    return rows


def read_samples(path):
    out = []
    for line in open(path):
        p = line.split()
        if len(p) == 3:
            out.append((int(p[0]), int(p[1]) * 100 // HZ, int(p[2])))
    return out


def idle_wall(samples, t0, t1, ncpu):
    """Projected wall centiseconds of the window [t0, t1) on an idle
    machine with ncpu CPUs (see the module comment)."""
    total = 0.0
    for (ta, ca, _), (tb, cb, rb) in zip(samples, samples[1:]):
        lo, hi = max(ta, t0), min(tb, t1)
        if hi <= lo:
            continue
        frac = (hi - lo) / (tb - ta)
        used = max(0, cb - ca) * frac
        if used > 0:
            total += used / max(1, min(rb, ncpu))
        else:
            total += hi - lo
    return total


def fmt(cs):
    return f"{cs / 100:.0f}"


def write(args):
    import argparse
    ap = argparse.ArgumentParser(prog="ci_budget.py write")
    ap.add_argument("--steps", required=True)
    ap.add_argument("--samples", required=True)
    ap.add_argument("--meta", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args(args)
    meta = {}
    for line in open(a.meta):
        k, _, v = line.rstrip("\n").partition("=")
        meta[k] = v
    ncpu = int(meta["cpus"])
    budget_s = int(meta["budget_minutes"]) * 60
    rows = read_steps(a.steps)
    samples = read_samples(a.samples)
    steps = [r for r in rows if r["kind"] == "step"]
    bgs = [r for r in rows if r["kind"] == "background"]
    t_begin = steps[0]["start"]
    t_end = max(r["start"] + r["wall"] for r in rows)
    cpu_total = sum(r["cpu"] for r in rows)
    proj_total = 0.0
    L = page_head("CI time budget", "../README.md", [
        "whoever adds a step to the test command: where `bash scripts/test-all`",
        "(CI's `.ci/run`) spends its time on a fresh clone, in CPU-seconds and wall seconds per step.",
        "Written by `scripts/ci-budget` from one run; do not edit.", ""])
    w = L.append
    w(f"Run: a fresh clone of `{meta['commit']}`, {meta['date']}, `nice -n {meta['nice']}`. Machine: {meta['machine']}, "
      f"{ncpu} CPUs, load average {meta['load_start']} at the start and {meta['load_end']} at the end "
      "(other jobs share the machine: the wall seconds below stretch with that load, the CPU-seconds hardly).")
    w("")
    w("Already installed before the run, so their download and install time is not in these figures: "
      + meta["present"] + ".")
    w("")
    w("Columns: **CPU s**, user + system seconds of every process the step ran (a background job's in its own")
    w("row, not in the step that waits for it); **wall s** as measured under that load; **idle wall s**, the")
    w(f"projection to an idle {ncpu}-CPU machine of the whole run during the step (background jobs included):")
    w("the run's process tree is sampled every half second, and the CPU-seconds used in an interval with R")
    w(f"threads runnable take CPU / min(R, {ncpu}) seconds there (an interval with no CPU used, a download or")
    w("a wait, keeps its length).")
    w("")
    w("| step | CPU s | wall s | idle wall s |")
    w("|---|---:|---:|---:|")
    for r in steps:
        pw = idle_wall(samples, r["start"], r["start"] + r["wall"], ncpu)
        proj_total += pw
        w(f"| {r['name']} | {fmt(r['cpu'])} | {fmt(r['wall'])} | {fmt(pw)} |")
    w("")
    w("Background jobs (they run beside the steps from the row's start to the step that waits for them):")
    w("")
    w("| background job | started (s from the start) | CPU s | wall s |")
    w("|---|---:|---:|---:|")
    for r in bgs:
        w(f"| {r['name']} | {fmt(r['start'] - t_begin)} | {fmt(r['cpu'])} | {fmt(r['wall'])} |")
    w("")
    procs_path = a.samples + ".procs"
    if os.path.exists(procs_path):
        w("Where the CPU-seconds went: per step, the programs with the most CPU-seconds (each process's own")
        w("user + system time as last sampled, by the step running when it was first seen; `rustc X` is")
        w("the compilation of crate X in any profile or target, summed; a background job's programs count in")
        w("the step they ran beside; processes shorter than the half-second sampling interval are missed, so")
        w("the rows add up to less than the step):")
        w("")
        w("| step | programs (CPU s) |")
        w("|---|---|")
        spans = [(r["start"], r["start"] + r["wall"], r["name"]) for r in steps]
        per = {}
        for line in open(procs_path):
            _, first, cs, lab = line.rstrip("\n").split("\t", 3)
            first, cs = int(first), int(cs)
            step = next((n for t0, t1, n in spans if t0 <= first < t1), spans[-1][2])
            per.setdefault(step, {}).setdefault(lab, 0)
            per[step][lab] += cs
        for _, _, n in spans:
            top = sorted(per.get(n, {}).items(), key=lambda kv: -kv[1])
            shown = [f"{lab} {fmt(cs)}" for lab, cs in top[:8] if cs >= 100]
            if shown:
                w(f"| {n.split(' (')[0]} | " + ", ".join(shown) + " |")
        w("")
    w(f"**Total: {fmt(cpu_total)} CPU-seconds; {fmt(t_end - t_begin)} s wall under this load; "
      f"projected on an idle {ncpu}-CPU machine {proj_total / 6000:.1f} min** (at least "
      f"{cpu_total / ncpu / 6000:.1f} min: every CPU busy throughout), plus the installs above on a new machine. "
      f"The budget is {budget_s // 60} minutes ({budget_s * ncpu} CPU-seconds on {ncpu} CPUs).")
    w("")
    open(a.out, "w").write("\n".join(L))
    print("\n".join(L))


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "sample":
        sample(sys.argv[2], sys.argv[3])
    elif len(sys.argv) > 1 and sys.argv[1] == "write":
        write(sys.argv[2:])
    else:
        sys.exit(__doc__)
