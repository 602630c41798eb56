#!/usr/bin/env python3
"""Mutation testing of the firmware crate: selection, runs, records, report.

Called by scripts/mutants (which installs cargo-mutants and sets the
environment); `scripts/mutants --help` documents the options.

Every mutant cargo-mutants lists for `raymip` (all CI feature sets but
`pcpi`, see FEATURES) gets a key that survives edits elsewhere: the hash of
its function (name, return type, text without comments and spacing), the
mutation (genre, replacement, original text) and its rank among identical
mutations of that function. A run writes one record file to
mutation/runs/ (one line per mutant tested: key, outcome, build and test
seconds, name); the report merges every record file, takes each key's
latest outcome, and writes the block of docs/reliability.md between
BEGIN and END: per module the mutants listed today, caught, missed,
unviable, timeouts, skipped as equivalent (mutation/equivalent.txt, one
line each with its reason) and the ones without a record (new or changed
code, to be run).
"""
import argparse
import hashlib
import json
import os
import platform
import re
import resource
import signal
import statistics
import subprocess
import sys
import time
from collections import Counter, defaultdict

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
RUNS = os.path.join(ROOT, "mutation", "runs")
EQUIVALENT = os.path.join(ROOT, "mutation", "equivalent.txt")
DOC = os.path.join(ROOT, "docs", "reliability.md")
BEGIN, END = "<!-- mutants:begin -->", "<!-- mutants:end -->"
PACKAGE = "raymip"
# Every CI feature set at once (the defaults come with `ffi`); the
# co-processor features `pcpi` and `cfu` build only for riscv32 (src/coproc
# is excluded in .cargo/mutants.toml).
FEATURES = "ffi,f32,raydiff,envmap"
OUTCOMES = {"CaughtMutant": "caught", "MissedMutant": "missed", "Unviable": "unviable",
            "Timeout": "timeout"}


def cargo_mutants(args, **kw):
    return subprocess.run(["cargo", "mutants", "-p", PACKAGE, "--features", FEATURES] + args,
                          cwd=ROOT, **kw)


def list_mutants():
    """The mutants cargo-mutants lists today, each with its key and module."""
    out = cargo_mutants(["--list", "--json"], check=True, capture_output=True, text=True).stdout
    mutants = json.loads(out)
    files, unbuilt = {}, {}
    rank = Counter()
    features = set(FEATURES.split(",")) | {"cone", "trilinear", "cache", "mipgen"}
    for m in mutants:
        path = m["file"]
        if path not in files:
            with open(os.path.join(ROOT, path), encoding="utf-8") as f:
                files[path] = f.read().split("\n")
        lines = files[path]
        fn = m.get("function") or {}
        fspan = fn.get("span")
        body = span_text(lines, fspan) if fspan else ""
        body = re.sub(r"//[^\n]*", "", body)
        body = " ".join(body.split())
        original = span_text(lines, m["span"])
        ident = "\x1f".join([fn.get("function_name", ""), fn.get("return_type", ""),
                             hashlib.sha1(body.encode()).hexdigest(), m["genre"],
                             m.get("replacement", ""), original])
        rank[ident] += 1
        m["key"] = hashlib.sha1(f"{ident}\x1f{rank[ident]}".encode()).hexdigest()[:16]
        m["module"] = module_of(path)
        if path not in unbuilt:
            unbuilt[path] = unbuilt_lines(lines, features)
        m["unbuilt"] = unbuilt[path].get(m["span"]["start"]["line"])
    mutants = [m for m in mutants if m["unbuilt"] != "test"]
    # Two identical functions in different files: tell them apart by path.
    seen = Counter(m["key"] for m in mutants)
    for m in mutants:
        if seen[m["key"]] > 1:
            m["key"] = hashlib.sha1(f"{m['key']}\x1f{m['file']}".encode()).hexdigest()[:16]
    return mutants


def span_text(lines, span):
    """Source text of a cargo-mutants span (1-based lines and columns, end exclusive)."""
    s, e = span["start"], span["end"]
    if s["line"] == e["line"]:
        return lines[s["line"] - 1][s["column"] - 1:e["column"] - 1]
    parts = [lines[s["line"] - 1][s["column"] - 1:]]
    parts += lines[s["line"]:e["line"] - 1]
    parts.append(lines[e["line"] - 1][:e["column"] - 1])
    return "\n".join(parts)


# The host build that tests the mutants: cfg predicates and their values.
HOST_CFG = {"target_arch": "x86_64", "target_pointer_width": "64", "target_os": "linux"}


def cfg_value(expr, features):
    """Value of a `#[cfg(...)]` predicate in the host test build (`test` false:
    `#[cfg(test)]` code holds no mutants)."""
    expr = expr.strip()
    m = re.match(r"^(all|any|not)\((.*)\)$", expr, re.S)
    if m:
        args, depth, cur = [], 0, ""
        for ch in m.group(2):
            if ch == "," and depth == 0:
                args.append(cur)
                cur = ""
                continue
            depth += (ch == "(") - (ch == ")")
            cur += ch
        if cur.strip():
            args.append(cur)
        vals = [cfg_value(a, features) for a in args]
        return {"all": all, "any": any}[m.group(1)](vals) if m.group(1) != "not" else not vals[0]
    m = re.match(r'^(\w+)\s*=\s*"([^"]*)"$', expr)
    if m:
        key, val = m.groups()
        if key == "feature":
            return val in features
        if key == "target_feature":
            return False
        return HOST_CFG.get(key) == val
    return False


def unbuilt_lines(lines, features):
    """{line (1-based): "test" or "unbuilt"} of the items, statements and
    blocks under a `#[cfg(...)]` that is false in the host test build:
    test code (the predicate names `test`; cargo-mutants skips only a plain
    `#[cfg(test)]`), or firmware the host build leaves out."""
    out = {}
    for i, line in enumerate(lines):
        m = re.match(r"^\s*#\[cfg\((.*)\)\]\s*$", line)
        if not m or cfg_value(m.group(1), features):
            continue
        kind = "test" if re.search(r"\btest\b", m.group(1)) else "unbuilt"
        # The attribute applies to what follows: up to the `;` or the
        # closing brace at nesting depth 0 (further attributes skipped).
        depth, j, done = 0, i + 1, False
        while j < len(lines) and not done:
            text = re.sub(r"//.*", "", lines[j])
            if depth == 0 and text.strip().startswith("#["):
                out.setdefault(j + 1, kind)
                j += 1
                continue
            out.setdefault(j + 1, kind)
            for ch in text:
                if ch in "({[":
                    depth += 1
                elif ch in ")}]":
                    depth -= 1
                    if depth == 0 and ch == "}":
                        done = True
                        break
                elif ch in ";," and depth == 0:
                    done = True
                    break
            j += 1
    return out


def module_of(path):
    """`src/texture/storage/mip.rs` -> `texture::storage::mip` (`mod.rs`: its folder)."""
    p = path[len("src/"):] if path.startswith("src/") else path
    p = p[:-3] if p.endswith(".rs") else p
    parts = [x for x in p.split("/") if x]
    if parts and parts[-1] == "mod":
        parts.pop()
    return "::".join(parts) or "lib"


def plain_name(m):
    """Mutant name without line and column: `src/x.rs: replace ...`."""
    return re.sub(r"^([^:]+):\d+:\d+: ", r"\1: ", m["name"])


def load_equivalent(mutants):
    """mutation/equivalent.txt -> {key: reason}; every entry must match exactly one mutant.

    Line form: `NAME-WITHOUT-LINE-COLUMN [#K] -- REASON` (`#K`: the K-th
    such mutant of the function, from 1, when the name is not unique).
    """
    by_plain = defaultdict(list)
    for m in mutants:
        by_plain[plain_name(m)].append(m)
    eq, errors = {}, []
    if not os.path.exists(EQUIVALENT):
        return eq, errors
    with open(EQUIVALENT, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if " -- " not in line:
                errors.append(f"mutation/equivalent.txt:{n}: no ' -- REASON'")
                continue
            name, reason = (x.strip() for x in line.split(" -- ", 1))
            k = None
            mk = re.match(r"^(.*) #(\d+)$", name)
            if mk:
                name, k = mk.group(1), int(mk.group(2))
            cands = by_plain.get(name, [])
            if k is not None:
                cands = cands[k - 1:k]
            if len(cands) != 1 or not reason:
                errors.append(f"mutation/equivalent.txt:{n}: matches {len(cands)} mutants "
                              f"(needs exactly one, and a reason): {name}")
                continue
            eq[cands[0]["key"]] = reason
    return eq, errors


def load_runs():
    """Every record file, oldest first: [(header dict, [(key, outcome, build, test, name)])]."""
    runs = []
    if not os.path.isdir(RUNS):
        return runs
    for fn in sorted(os.listdir(RUNS)):
        if not fn.endswith(".tsv"):
            continue
        header, rows = {}, []
        with open(os.path.join(RUNS, fn), encoding="utf-8") as f:
            for line in f:
                line = line.rstrip("\n")
                if line.startswith("# "):
                    k, _, v = line[2:].partition(": ")
                    header[k] = v
                elif line and not line.startswith("key\t"):
                    key, outcome, build, test, name = line.split("\t", 4)
                    rows.append((key, outcome, float(build), float(test), name))
        header["file"] = fn
        runs.append((header, rows))
    runs.sort(key=lambda r: r[0].get("started", r[0]["file"]))
    return runs


def latest(runs):
    """{key: (outcome, build s, test s, run header)} from the newest record of each key."""
    out = {}
    for header, rows in runs:
        for key, outcome, build, test, _ in rows:
            out[key] = (outcome, build, test, header)
    return out


def machine():
    model = ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{platform.machine()} {platform.system().lower()}, {os.cpu_count()} CPUs" + (
        f" ({model})" if model else "")


def escape_name(name):
    return "^" + re.escape(name) + "$"


def run(args):
    mutants = list_mutants()
    eq, errors = load_equivalent(mutants)
    if errors:
        sys.exit("\n".join(errors))
    recorded = latest(load_runs())
    todo = [m for m in mutants if m["key"] not in eq and not m["unbuilt"]]
    label = "all"
    if args.file:
        todo = [m for m in todo if any(m["file"] == f or m["file"].startswith(f.rstrip("/") + "/")
                                       for f in args.file)]
        label = "+".join(module_of(f.rstrip("/")).replace("::", ".") for f in args.file)
    if args.in_diff is not None:
        base = args.in_diff or last_doc_commit()
        changed = changed_lines(base)
        todo = [m for m in todo if overlaps(m, changed)]
        label = f"diff-{base[:10]}"
    if args.unrecorded:
        todo = [m for m in todo if m["key"] not in recorded]
        label += "-unrecorded"
    if args.caught:
        todo = [m for m in todo if recorded.get(m["key"], ("",))[0] == "caught"]
        label += "-caught"
    if args.missed:
        todo = [m for m in todo if recorded.get(m["key"], ("",))[0] in ("missed", "timeout")]
        label += "-missed"
    if args.shard:
        k, n = (int(x) for x in args.shard.split("/"))
        if not 0 <= k < n:
            sys.exit(f"--shard {args.shard}: need 0 <= k < n")
        # Slices of the listing in source order (neighbouring mutants share
        # incremental builds), the same split as cargo-mutants' --shard.
        todo = todo[len(todo) * k // n:len(todo) * (k + 1) // n]
        label += f"-shard-{k}-of-{n}"
    if args.window and len(todo) > args.window:
        # A window of consecutive mutants that moves on by its length with
        # every commit: successive CI runs cover the whole selection.
        count = int(subprocess.run(["git", "rev-list", "--count", "HEAD"], cwd=ROOT,
                                   capture_output=True, text=True).stdout.strip() or 0)
        start = count * args.window % len(todo)
        todo = (todo + todo)[start:start + args.window]
        label += f"-window-{start}"
    if args.limit is not None:
        todo = todo[:args.limit]
    print(f"mutants: {len(todo)} of {len(mutants)} to test ({label}; "
          f"{len(eq)} skipped as equivalent)", flush=True)
    if args.list:
        for m in todo:
            print(m["name"])
        return 0
    if not todo:
        return report(args, quiet=True)
    out_dir = args.out
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "examine.txt"), "w", encoding="utf-8") as f:
        for m in todo:
            f.write(escape_name(m["name"]) + "\n")
    by_name = {m["name"]: m for m in mutants if m["key"] not in eq}
    whole = len(todo) == len(mutants) - len(eq) - sum(1 for m in mutants if m["unbuilt"])
    tree, lock = run_tree()
    fingerprint = sync_tree(tree)
    clean = tree + ".clean"
    if not os.path.exists(clean):
        forget_builds(tree)
    else:
        os.remove(clean)
    # Stage "lib" tests each mutant with the unit tests only (`cargo test
    # --lib`: one test binary to build, not three); a mutant they catch is
    # caught. Only the ones they miss (or that time out) go on to stage
    # "all", every test of the crate; only its outcomes can be "missed".
    # Before it, stage "module" runs the same test binary with only the
    # unit tests of the mutated files' modules (a libtest name filter per
    # module): the same build, a fraction of the test run (the slowest unit
    # tests are other modules' brute-force sweeps), and a mutant they catch
    # is caught by a real test too; the rest go on to stage "lib".
    stages = ["all"] if args.all_tests else ["lib", "all"]
    filters = module_filters(todo)
    if not args.all_tests and not args.no_module_tests and filters:
        stages.insert(0, "module")
    clock = {"deadline": None, "stop": 0, "stopping": None, "grace": args.stop_grace}

    def stop(signum, frame):
        # SIGINT or SIGTERM: end like the time box (record what finished,
        # run no further stage); a second one ends without waiting for the
        # running build.
        clock["stop"] += 1

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    records, timed_out, build_killed = [], False, False
    for stage in stages:
        if not todo or timed_out:
            break
        rec, timed_out, build_killed = run_stage(args, stage, todo, whole and stage == stages[0], mutants, eq,
                                   by_name, tree, fingerprint, os.path.join(out_dir, stage),
                                   label, clock, filters)
        records.append(rec)
        if not rec.baseline_ok:
            sys.exit("cargo mutants: the unmutated tree failed its build or tests (baseline)")
        done = {r[4] for r in rec.rows if stage == "all" or r[1] in ("caught", "unviable")}
        todo = [m for m in todo if m["name"] not in done]
    if not build_killed:
        # No build of this run was killed: the next run may build on it.
        open(clean, "w").close()
    lock.close()
    rows = [r for rec in records for r in rec.rows]
    counts = Counter(r[1] for r in rows)
    print(f"mutants: recorded {len(rows)} in "
          + ", ".join(os.path.relpath(rec.path, ROOT) for rec in records if rec.rows) + ": "
          + ", ".join(f"{counts[o]} {o}" for o in OUTCOMES.values())
          + (f"; stopped (time box or signal), {len(todo)} not run to the end"
             if timed_out else ""))
    bad = [r for r in rows if r[1] in ("missed", "timeout")]
    for r in bad:
        print(f"  {r[1].upper()}: {r[4]}")
    if not args.no_report:
        report(args, quiet=True)
    return 1 if bad else 0


def module_filters(todo):
    """libtest name filters that select the unit tests of TODO's files:
    `texture::storage::mip::` for src/texture/storage/mip.rs (a folder's
    mod.rs: the folder's module and its submodules). None when a mutant
    lies in the crate root (its tests have no module prefix)."""
    mods = sorted({module_of(m["file"]) for m in todo})
    if not mods or "lib" in mods:
        return None
    return [f"{mod}::" for mod in mods]


def run_stage(args, stage, todo, whole, mutants, eq, by_name, tree, fingerprint, out_dir, label,
              clock, filters=None):
    """One cargo-mutants run over TODO in TREE with the tests of STAGE
    ("module", "lib" or "all"; FILTERS: the module stage's test name
    filters); returns its Record and whether the time box ended it."""
    cmd = ["--no-shuffle", "-o", out_dir, "--colors", "never", "--in-place"]
    if stage in ("module", "lib"):
        # -C: the build (cargo test --no-run) and the test run both.
        cmd += ["--cargo-arg=--lib"]
    if stage == "module":
        # After `--`: libtest runs the tests whose names contain a filter.
        cmd += ["--cargo-test-arg=--"] + [f"--cargo-test-arg={f}" for f in filters]
    if not whole:
        # cargo-mutants 27.1 applies name filters to every genre but
        # StructField: the file filter keeps those to the selected files
        # (and their outcomes are recorded too).
        for f in sorted({m["file"] for m in todo}):
            cmd += ["-f", f]
        for m in todo:
            cmd += ["-F", escape_name(m["name"])]
    else:
        for m in mutants:
            if m["key"] in eq or m["unbuilt"]:
                cmd += ["-E", escape_name(m["name"])]
    baseline = read_baseline(tree, fingerprint,
                             stage if stage != "module" else "module " + " ".join(filters))
    if baseline is not None:
        # These tests passed on this tree in this target directory:
        # cargo-mutants gets the timeout its baseline would have set (5
        # times the unmutated test run, at least the minimum of
        # .cargo/mutants.toml).
        timeout = max(MINIMUM_TEST_TIMEOUT, 5 * baseline)
        cmd += ["--baseline", "skip", "--timeout", f"{timeout:.0f}"]
        print(f"mutants: {stage} tests: baseline skipped (they passed on this tree in "
              f"{baseline:.0f} s); test timeout {timeout:.0f} s", flush=True)
    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    rec = Record(started, label + ("" if stage == "all" else "-" + stage), len(todo), by_name,
                 os.path.join(out_dir, "mutants.out", "outcomes.json"), stage)
    rec.filters = filters
    rec.baseline_done = baseline is not None
    tests = {"module": "unit tests of " + " ".join(filters or []) + " (--lib)",
             "lib": "unit tests (--lib)", "all": "every test"}[stage]
    print(f"mutants: {len(todo)} with the {tests}",
          flush=True)
    proc = subprocess.Popen(["cargo", "mutants", "-p", PACKAGE, "--features", FEATURES] + cmd,
                            cwd=tree, start_new_session=True)
    timed_out = build_killed = False
    while proc.poll() is None:
        # The record is rewritten as outcomes arrive: an interrupted run
        # keeps what it finished.
        rec.update(proc.pid)
        if args.time_box and clock["deadline"] is None and rec.baseline_done:
            # The time box counts from the end of the first baseline (the
            # unmutated build and one run of the tests): mutants only.
            clock["deadline"] = time.monotonic() + args.time_box
        if clock["stop"] or (clock["deadline"] and time.monotonic() > clock["deadline"]):
            if clock["stopping"] is None:
                clock["stopping"] = time.monotonic()
            # A rustc killed mid-build can leave an incremental state that
            # the next run must throw away (forget_builds: a full rebuild
            # of the crate). Up to the grace period, wait for the running
            # mutant's build to end: SIGINT in its test phase keeps the
            # state whole. A second signal stops at once.
            waited = time.monotonic() - clock["stopping"]
            if clock["stop"] < 2 and waited < clock["grace"] and building(proc.pid):
                time.sleep(0.5)
                continue
            timed_out = True
            build_killed = building(proc.pid)
            # cargo-mutants stops on SIGINT, kills its cargo and puts the
            # mutated file back; what it finished is in outcomes.json.
            os.killpg(proc.pid, signal.SIGINT)
            try:
                proc.wait(timeout=60)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
                build_killed = True
            print(f"mutants: stopped {waited:.0f} s after the time box or signal, "
                  + ("during a build (the next run rebuilds the crate)" if build_killed
                     else "outside a build (the next run builds on this one)"), flush=True)
            break
        time.sleep(5)
    rec.update(None, timed_out=timed_out)
    if rec.baseline_test is not None:
        write_baseline(tree, fingerprint,
                       stage if stage != "module" else "module " + " ".join(filters),
                       rec.baseline_test)
    return rec, timed_out, build_killed


def building(pid):
    """Whether a rustc runs under process PID (cargo-mutants): the build
    phase of a mutant, or of the baseline."""
    children = defaultdict(list)
    names = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat", encoding="utf-8") as f:
                stat = f.read()
        except OSError:
            continue
        name = stat[stat.index("(") + 1:stat.rindex(")")]
        ppid = int(stat[stat.rindex(")") + 2:].split()[1])
        children[ppid].append(int(d))
        names[int(d)] = name
    todo = list(children[pid])
    while todo:
        p = todo.pop()
        if names.get(p) == "rustc":
            return True
        todo.extend(children[p])
    return False


class Record:
    """One run's record file in mutation/runs/, rewritten from outcomes.json."""

    def __init__(self, started, label, selected, by_name, outcomes_file, stage="all"):
        self.started, self.label, self.selected = started, label, selected
        self.stage = stage
        self.by_name, self.outcomes_file = by_name, outcomes_file
        self.path = os.path.join(RUNS, f"{started.replace(':', '').replace('-', '')}-{label}.tsv")
        self.load0 = os.getloadavg()[0]
        self.t0 = time.monotonic()
        self.ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        self.cpu_live = 0.0
        self.rows, self.baseline_ok, self.baseline_done, self.version = [], True, False, "?"
        self.baseline_test = None
        self.filters = None
        self.commit = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT,
                                     capture_output=True, text=True).stdout.strip()
        self.dirty = subprocess.run(["git", "status", "--porcelain", "--", "src", "tests"],
                                    cwd=ROOT, capture_output=True, text=True).stdout.strip()

    def update(self, pid, timed_out=False):
        if pid is not None:
            self.cpu_live = process_cpu(pid)
            cpu = self.cpu_live
        else:
            ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (ru1.ru_utime - self.ru0.ru_utime) + (ru1.ru_stime - self.ru0.ru_stime)
        try:
            with open(self.outcomes_file, encoding="utf-8") as f:
                outcomes = json.load(f)
        except (OSError, ValueError):
            return
        self.version = outcomes.get("cargo_mutants_version", "?")
        rows = []
        for o in outcomes["outcomes"]:
            sc = o["scenario"]
            if sc == "Baseline":
                self.baseline_ok = o["summary"] == "Success"
                self.baseline_done = True
                if self.baseline_ok:
                    self.baseline_test = sum(p["duration"] for p in o["phase_results"]
                                             if p["phase"] == "Test")
                continue
            name = sc["Mutant"]["name"]
            m = self.by_name.get(name)
            if m is None or o["summary"] not in OUTCOMES:
                continue
            d = {p["phase"]: p["duration"] for p in o["phase_results"]}
            if self.stage != "all" and OUTCOMES[o["summary"]] in ("missed", "timeout"):
                # Not missed yet: the next stage runs it with every test.
                continue
            rows.append((m["key"], OUTCOMES[o["summary"]], d.get("Build", 0.0),
                         d.get("Test", 0.0), name))
        self.rows = rows
        if not rows or not self.baseline_ok:
            return
        os.makedirs(RUNS, exist_ok=True)
        tmp = self.path + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(f"# started: {self.started}\n")
            f.write(f"# selection: {self.label}\n")
            f.write(f"# commit: {self.commit}{' + uncommitted changes' if self.dirty else ''}\n")
            f.write(f"# cargo-mutants: {self.version}\n")
            f.write(f"# features: {FEATURES}\n")
            f.write(f"# machine: {machine()}\n")
            f.write(f"# load average: {self.load0:.1f} at start, {os.getloadavg()[0]:.1f} "
                    "at end\n")
            f.write(f"# nice: {os.nice(0)}\n")
            if self.stage == "module":
                f.write("# tests: the unit tests of " + " ".join(self.filters) + " (cargo test "
                        "--lib -- FILTERS); the mutants they missed are in the next record, "
                        "run with every unit test\n")
            if self.stage == "lib":
                f.write("# tests: the unit tests (cargo test --lib); the mutants they missed "
                        "are in the next record, run with every test\n")
            f.write(f"# wall seconds: {time.monotonic() - self.t0:.0f}\n")
            f.write(f"# cpu seconds: {cpu:.0f}\n")
            f.write(f"# mutants tested: {len(rows)} of {self.selected} selected"
                    f"{' (time box reached)' if timed_out else ''}"
                    f"{' (running)' if pid is not None else ''}\n")
            f.write("key\toutcome\tbuild_s\ttest_s\tname\n")
            for r in rows:
                f.write(f"{r[0]}\t{r[1]}\t{r[2]:.1f}\t{r[3]:.1f}\t{r[4]}\n")
        os.replace(tmp, self.path)


# .cargo/mutants.toml's minimum_test_timeout (s): the floor of the timeout
# given to cargo-mutants when the baseline is skipped.
MINIMUM_TEST_TIMEOUT = 120


def run_tree():
    """The directory cargo-mutants mutates in place, and its lock.

    A fixed copy of the work tree per target directory (cargo-mutants' own
    copy has a new name each run, so every run rebuilt the crate from
    scratch before its first mutant): with the same path, the incremental
    build of the last run is reused. Outside the checkout, so no other
    .cargo/config.toml applies."""
    import fcntl
    target = os.path.abspath(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")))
    tag = hashlib.sha1(target.encode()).hexdigest()[:10]
    tree = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"raymip-mutants-{tag}")
    os.makedirs(tree, exist_ok=True)
    lock = open(tree + ".lock", "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        print(f"mutants: waiting for the run that uses {tree} (same target directory)",
              flush=True)
        fcntl.flock(lock, fcntl.LOCK_EX)
    return tree, lock


def forget_builds(tree):
    """Start the crate's builds afresh: the last run in TREE was stopped (time
    box, interrupt) or never ran. A rustc killed mid-build can leave an
    incremental state from which a later build of the reverted source
    still contains the mutant (seen once: the unmutated tree then fails its
    own tests), so the crate's incremental states and the baseline record
    go, and the crate roots are touched to rebuild every test binary."""
    import glob
    import shutil
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    for d in glob.glob(os.path.join(target, "*", "incremental", "*")):
        if os.path.basename(d).split("-")[0] in ("raymip", "firmware"):
            shutil.rmtree(d, ignore_errors=True)
    for f in (tree + ".baseline.json",):
        if os.path.exists(f):
            os.remove(f)
    now = time.time()
    for f in ("src/lib.rs", "tests/firmware/main.rs"):
        if os.path.exists(os.path.join(tree, f)):
            os.utime(os.path.join(tree, f), (now, now))


def sync_tree(tree):
    """Make TREE hold the work tree's files (tracked and untracked, not
    ignored; what cargo-mutants would copy): only files whose content
    differs are written (a new mtime: cargo rebuilds what changed, and a
    file a killed run left mutated is restored). Returns the fingerprint of
    the content, with the toolchain and the features."""
    files = subprocess.run(["git", "ls-files", "-z", "-co", "--exclude-standard"], cwd=ROOT,
                           capture_output=True, check=True).stdout.decode().split("\0")
    files = sorted(f for f in files if f and os.path.isfile(os.path.join(ROOT, f)))
    h = hashlib.sha1()
    for tool in (["rustc", "-vV"], ["cargo", "mutants", "--version"]):
        h.update(subprocess.run(tool, capture_output=True, check=True).stdout)
    h.update(FEATURES.encode())
    keep = set(files)
    for f in files:
        with open(os.path.join(ROOT, f), "rb") as src:
            data = src.read()
        # Every run rewrites its record and the report's block: neither
        # is code, and the block's text (counts, times, mutant names) quotes
        # no constant that tests/firmware/doc_tables.rs checks, so they
        # leave the fingerprint out (the equivalent list stays in), as do
        # the scripts (the crate's tests never read scripts/).
        if f.startswith(("mutation/runs/", "scripts/")):
            pass
        elif f == os.path.relpath(DOC, ROOT):
            text = data.decode()
            if BEGIN in text and END in text:
                text = text[:text.index(BEGIN)] + text[text.index(END):]
            h.update(f.encode() + b"\0" + hashlib.sha1(text.encode()).digest())
        else:
            h.update(f.encode() + b"\0" + hashlib.sha1(data).digest())
        dst = os.path.join(tree, f)
        try:
            with open(dst, "rb") as old:
                if old.read() == data:
                    continue
        except OSError:
            os.makedirs(os.path.dirname(dst), exist_ok=True)
        with open(dst, "wb") as out:
            out.write(data)
        os.chmod(dst, os.stat(os.path.join(ROOT, f)).st_mode & 0o777)
    for d, _, names in os.walk(tree):
        for n in names:
            rel = os.path.relpath(os.path.join(d, n), tree)
            if rel not in keep:
                os.remove(os.path.join(d, n))
    return h.hexdigest()


def read_baseline(tree, fingerprint, stage):
    """Seconds of the unmutated test run when this exact tree (fingerprint)
    passed STAGE's tests ("module FILTERS", "lib" or "all"; each includes
    the ones before) in this target directory, else None. The
    environment's MUTANTS_BASELINE=run forces a baseline."""
    if os.environ.get("MUTANTS_BASELINE", "auto") == "run":
        return None
    try:
        with open(tree + ".baseline.json", encoding="utf-8") as f:
            b = json.load(f)
    except (OSError, ValueError):
        return None
    if b.get("fingerprint") != fingerprint:
        return None
    t = b.get(stage, b.get("lib", b.get("all")) if stage.startswith("module") else b.get("all"))
    return None if t is None else float(t)


def write_baseline(tree, fingerprint, stage, test_s):
    b = {}
    try:
        with open(tree + ".baseline.json", encoding="utf-8") as f:
            b = json.load(f)
    except (OSError, ValueError):
        pass
    if b.get("fingerprint") != fingerprint:
        b = {"fingerprint": fingerprint}
    b[stage] = test_s
    with open(tree + ".baseline.json", "w", encoding="utf-8") as f:
        json.dump(b, f)


def process_cpu(pid):
    """CPU seconds of a running process and its waited-for descendants (/proc)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="utf-8") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return sum(int(x) for x in fields[11:15]) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return 0.0


def last_doc_commit():
    out = subprocess.run(["git", "log", "-1", "--format=%H", "--", "docs/reliability.md"],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
    if not out:
        print("mutants: no commit touched docs/reliability.md (shallow clone?): no diff")
        return "HEAD"
    return out


def changed_lines(base):
    """{path: set of changed line numbers in the work tree} since BASE."""
    diff = subprocess.run(["git", "diff", "-U0", base, "--", "src"], cwd=ROOT,
                          capture_output=True, text=True, check=True).stdout
    changed, path = defaultdict(set), None
    for line in diff.split("\n"):
        if line.startswith("+++ "):
            path = line[6:] if line.startswith("+++ b/") else None
        elif line.startswith("@@") and path:
            mh = re.match(r"@@ -\S+ \+(\d+)(?:,(\d+))? @@", line)
            start, count = int(mh.group(1)), int(mh.group(2) or 1)
            changed[path].update(range(start, start + max(count, 1)))
    return changed


def overlaps(m, changed):
    lines = changed.get(m["file"])
    if not lines:
        return False
    fn = (m.get("function") or {}).get("span") or m["span"]
    return any(fn["start"]["line"] <= n <= fn["end"]["line"] for n in lines)


def report(args, quiet=False):
    mutants = list_mutants()
    eq, errors = load_equivalent(mutants)
    if errors:
        sys.exit("\n".join(errors))
    runs = load_runs()
    rec = latest(runs)
    cols = ["caught", "missed", "timeout", "unviable", "equivalent", "not built", "unrecorded"]
    per = defaultdict(Counter)
    used_runs, times, missed, unbuilt = {}, [], [], []
    for m in mutants:
        c = per[m["module"]]
        c["mutants"] += 1
        if m["key"] in eq:
            c["equivalent"] += 1
        elif m["unbuilt"]:
            c["not built"] += 1
            unbuilt.append(m["name"])
        elif m["key"] in rec:
            outcome, build, test, header = rec[m["key"]]
            c[outcome] += 1
            used_runs[header["file"]] = header
            if outcome != "unviable":
                times.append((build, test))
            if outcome in ("missed", "timeout"):
                missed.append((outcome, m["name"]))
        else:
            c["unrecorded"] += 1
    total = Counter()
    for c in per.values():
        total.update(c)
    lines = [BEGIN]
    if used_runs:
        starts = sorted(h.get("started", "?")[:10] for h in used_runs.values())
        machines = sorted({h.get("machine", "?") for h in used_runs.values()})
        versions = sorted({h.get("cargo-mutants", "?") for h in used_runs.values()})
        cpu = sum(float(h.get("cpu seconds", 0)) for h in used_runs.values())
        wall = sum(float(h.get("wall seconds", 0)) for h in used_runs.values())
        n_tested = sum(int(h.get("mutants tested", "0").split()[0]) for h in used_runs.values())
        loads = [float(x.split()[0]) for h in used_runs.values()
                 for x in h.get("load average", "").split(",")[:1] if x.strip()]
    lines.append(
        f"Written by `scripts/mutants` from {len(used_runs)} recorded runs in `mutation/runs/`"
        + (f" ({starts[0]} to {starts[-1]}; cargo-mutants {', '.join(versions)}; "
           f"{'; '.join(machines)})" if used_runs else "")
        + f", against the {total['mutants']} mutants cargo-mutants lists today for the "
        f"firmware crate with features `{FEATURES}` (every CI feature set but the riscv32 "
        "co-processors' `pcpi` and `cfu`: their modules in `src/coproc` are not mutated; test "
        "code is not either). Each "
        "mutant's newest record counts; a mutant whose function changed since its record "
        "is *unrecorded* until it is run again. Timeouts count as missed.")
    lines.append("")
    lines.append("| module | mutants | " + " | ".join(cols) + " |")
    lines.append("|---|" + "---:|" * (len(cols) + 1))
    for mod in sorted(per):
        c = per[mod]
        lines.append(f"| `{mod}` | {c['mutants']} | " + " | ".join(str(c[k]) for k in cols) + " |")
    lines.append(f"| **total** | **{total['mutants']}** | "
                 + " | ".join(f"**{total[k]}**" for k in cols) + " |")
    lines.append("")
    if times:
        b = statistics.median(t[0] for t in times)
        t = statistics.median(t[1] for t in times)
        mean = statistics.mean(x[0] + x[1] for x in times)
        lines.append(
            f"Time per mutant (build + test, wall, `nice`d on a shared machine, load average "
            f"{min(loads):.1f} to {max(loads):.1f} at the runs' starts): median {b:.1f} s + "
            f"{t:.1f} s, mean {mean:.1f} s; {cpu / max(n_tested, 1):.1f} CPU-seconds per mutant "
            f"over the runs ({wall / 3600:.1f} h wall, {cpu / 3600:.1f} CPU-hours, baselines "
            "included).")
        lines.append("")
    if missed:
        lines.append("Missed (a test must kill each):")
        lines.append("")
        for outcome, name in sorted(missed, key=lambda x: x[1]):
            lines.append(f"- {outcome}: `{name}`")
        lines.append("")
    if unbuilt:
        lines.append(
            f"Not built on the host ({len(unbuilt)}): code under a `#[cfg]` that the host "
            "test build leaves out: the co-processor paths (`pcpi`, `cfu` on riscv32, "
            "checked bit for bit by the soft-core testbenches), and code for a feature set "
            "without `cone` or `trilinear` (built by `scripts/features`, not tested on the "
            "host). Each is listed here:")
        lines.append("")
        for name in unbuilt:
            lines.append(f"- `{name}`")
        lines.append("")
    if eq:
        lines.append(f"Skipped as equivalent ({len(eq)}, "
                     f"{100 * len(eq) / max(total['mutants'], 1):.2f} %; "
                     "`mutation/equivalent.txt`):")
        lines.append("")
        by_key = {m["key"]: m for m in mutants}
        for key, reason in sorted(eq.items(), key=lambda kv: by_key[kv[0]]["name"]):
            lines.append(f"- `{plain_name(by_key[key])}`: {reason}")
        lines.append("")
    if lines[-1] == "":
        lines.pop()
    lines.append(END)
    block = "\n".join(lines)
    with open(DOC, encoding="utf-8") as f:
        doc = f.read()
    if BEGIN in doc:
        new = doc[:doc.index(BEGIN)] + block + doc[doc.index(END) + len(END):]
    else:
        sys.exit(f"docs/reliability.md has no {BEGIN} ... {END} block")
    if new != doc:
        with open(DOC, "w", encoding="utf-8") as f:
            f.write(new)
    if not quiet:
        print(block)
    print(f"mutants: docs/reliability.md block: {total['caught']} caught, {total['missed']} "
          f"missed, {total['timeout']} timeout, {total['unviable']} unviable, "
          f"{total['equivalent']} equivalent, {total['not built']} not built, "
          f"{total['unrecorded']} unrecorded "
          f"of {total['mutants']}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shard", metavar="K/N", help="the K-th of N slices of the selection (0-based)")
    ap.add_argument("--in-diff", nargs="?", const="", metavar="BASE",
                    help="mutants in functions changed since BASE (default: the last commit "
                         "that touched docs/reliability.md)")
    ap.add_argument("--unrecorded", action="store_true",
                    help="only mutants without a record (new or changed code)")
    ap.add_argument("--caught", action="store_true",
                    help="only mutants whose newest record is caught (re-verification)")
    ap.add_argument("--missed", action="store_true",
                    help="only mutants whose newest record is missed or timeout")
    ap.add_argument("--file", action="append", help="only mutants in this file or folder")
    ap.add_argument("--limit", type=int, help="at most this many mutants")
    ap.add_argument("--window", type=int, metavar="N",
                    help="N consecutive mutants of the selection, starting N further on with "
                         "each commit (git rev-list --count HEAD)")
    ap.add_argument("--time-box", type=float, metavar="S",
                    help="stop cargo-mutants S seconds after its baseline (the unmutated "
                         "build and tests); what finished is recorded")
    ap.add_argument("--stop-grace", type=float, default=120, metavar="S",
                    help="at the time box or a signal, wait up to S s for the running "
                         "mutant's build to end, so the next run builds on this one "
                         "(0: stop at once)")
    ap.add_argument("--all-tests", action="store_true",
                    help="test every mutant with every test (default: the unit tests first, "
                         "every test only for the mutants they miss)")
    ap.add_argument("--no-module-tests", action="store_true",
                    help="no first stage with only the mutated modules' unit tests (CI's --ci)")
    ap.add_argument("--list", action="store_true", help="print the selection, run nothing")
    ap.add_argument("--report", action="store_true",
                    help="only rewrite the docs/reliability.md block from the records")
    ap.add_argument("--no-report", action="store_true", help="record, but leave the block")
    ap.add_argument("--out", default=None, help="cargo-mutants output directory")
    args = ap.parse_args()
    if args.report:
        return report(args)
    if args.out is None and not args.list:
        sys.exit("--out DIR is required (scripts/mutants gives a temporary one)")
    return run(args)


if __name__ == "__main__":
    sys.exit(main())
