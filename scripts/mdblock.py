"""The generated Markdown of the measurement scripts: the head of a
measurement page (scripts/budgets.py, scripts/ci_budget.py); for the blocks
that scripts/fpga.py and scripts/softcore.py write into pages, their
command line, a block between a begin and an end marker replaced by the
script's new text, the figures a block carries for another script as a
data comment, and the page written or, with --check, its difference from
the new text printed."""
import argparse
import difflib
import json
import os
import re
import sys


def page_head(title, readme, lede):
    """The first lines of a measurement page: its title, the link back to
    the README (`readme`: its path from the page) and the lede, whose first
    line continues "**Measurement page** for " (whom the page serves, what
    it measures, which script writes it)."""
    return [f"# {title}", "", f"[← README]({readme})", "", "**Measurement page** for " + lede[0], *lede[1:]]


def markers(name):
    """The begin and end markers of the block `name`."""
    return f"<!-- {name}:begin -->", f"<!-- {name}:end -->"


def data_comment(name, data):
    """The comment that carries `data` (JSON) in a block, as `read_data`
    reads it."""
    return f"<!-- {name}-data: {json.dumps(data, sort_keys=True)} -->"


def read_data(text, name):
    """The data of the comment `name` in `text` (`data_comment`), None
    without one."""
    m = re.search(rf"<!-- {re.escape(name)}-data: (\{{.*?\}}) -->", text)
    return json.loads(m.group(1)) if m else None


def parse_args(self_test, values, numbers=(), flags=()):
    """The command line of a block-writing script: `--NAME TEXT` for each
    name in `values`, `--NAME N` (an integer) for each in `numbers`,
    `--NAME` for `--check` and each in `flags`; `--self-test` runs
    `self_test` and exits."""
    ap = argparse.ArgumentParser()
    for k in values:
        ap.add_argument(f"--{k}")
    for k in numbers:
        ap.add_argument(f"--{k}", type=int)
    for k in ("check", *flags):
        ap.add_argument(f"--{k}", action="store_true")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        self_test()
        sys.exit(0)
    return a


def replace_block(text, begin, end, block, after=None, before=None):
    """`text` with its block from `begin` to `end` (markers included)
    replaced by `block`. Without such a block, `block` goes after the text
    `after` or, else, before the text `before` (a blank line between), or
    else at the end."""
    i, j = text.find(begin), text.find(end)
    if i >= 0 and j > i:
        return text[:i] + block + text[j + len(end):]
    if after and after in text:
        k = text.index(after) + len(after)
        return text[:k] + "\n\n" + block + text[k:]
    if before and before in text:
        k = text.index(before)
        return text[:k] + block + "\n\n" + text[k:]
    return text.rstrip("\n") + "\n\n" + block + "\n"


def update(tool, path, old, new, check, rerun):
    """Writes `new` over `path` (whose text is `old`) or, with `check`,
    prints their difference and `rerun`, the command that would write it;
    whether they differ. `tool` prefixes each message."""
    name = os.path.basename(path)
    if new == old:
        print(f"{tool}: {name} is up to date")
        return False
    if check:
        print(f"{tool}: {name} differs from this measurement ({rerun} and commit it):")
        sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True), path, path + " (measured)"))
    else:
        open(path, "w").write(new)
        print(f"{tool}: wrote {name}")
    return True
