"""Shared plumbing of the figure scripts (peeling_figures.py, bending_figures.py): the command line,
finding the fibrane executable, running case variants resumably and in parallel, reading CSV output,
saving figures. Run the scripts with /usr/bin/python3 (Debian's numpy and matplotlib)."""
import argparse
import csv
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def command_line(description, script):
    """Parses --jobs, --only, --quick, --fibrane, --no-run; args.fibrane is the executable to use."""
    p = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--jobs", type=int, default=1, help="runs in parallel (each with one thread)")
    p.add_argument("--only", help="run only the variants whose name contains one of these (comma-separated) texts")
    p.add_argument("--quick", action="store_true", help="coarse meshes (smoke test)")
    p.add_argument("--fibrane", default=None, help="the fibrane executable (default: newest build*/app/fibrane)")
    p.add_argument("--no-run", action="store_true", help="only draw from existing results")
    args = p.parse_args()
    args.fibrane = args.fibrane or os.environ.get("FIBRANE_BIN")
    if not args.fibrane:
        found = sorted(ROOT.glob("build*/app/fibrane"), key=lambda f: f.stat().st_mtime)
        if not found:
            sys.exit(f"{script}: no fibrane executable (build it, or pass --fibrane)")
        args.fibrane = str(found[-1])
    return args


def selected(variants, only):
    """The variants whose names contain one of the comma-separated texts of --only (all without it)."""
    wanted = only.split(",") if only else []
    return {n: e for n, e in variants.items() if not wanted or any(w in n for w in wanted)}


def is_finished(directory, min_steps=0):
    """A run that completed, or stalled at a limit point ("dt below dt_min") after min_steps steps."""
    try:
        s = json.loads((directory / "summary.json").read_text())
    except (OSError, ValueError):
        return False
    return s.get("completed", False) or ("dt below dt_min" in s.get("message", "") and s.get("steps", 0) > min_steps)


def run_case(fibrane, name, text, results, out):
    """Writes the case text to results/<name>.yaml and runs it into `out` (log: results/<name>.log)."""
    case = results / f"{name}.yaml"
    case.write_text(text)
    start = time.time()
    with open(results / f"{name}.log", "w") as log:
        code = subprocess.call([fibrane, "run", str(case), "-o", str(out), "--threads", "1", "-q"],
                               stdout=log, stderr=subprocess.STDOUT)
    print(f"  {name}: exit {code} after {time.time() - start:.0f} s")


def run_all(todo, run_variant, jobs):
    """Calls run_variant(name, edits) for every variant, `jobs` at a time."""
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for f in [pool.submit(run_variant, n, e) for n, e in todo.items()]:
            f.result()


def read_csv(path):
    """The numeric columns of a CSV file as a dict of column name -> numpy array (text columns, such as the
    interaction CSV's status, are left out; "nan" entries are numbers)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))

    def numeric(k):
        try:
            [float(r[k]) for r in rows]
            return True
        except ValueError:
            return False
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0] if numeric(k)}


def save(fig, path, dpi=90):
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    import matplotlib.pyplot as plt
    plt.close(fig)
    print(f"  wrote {path.relative_to(ROOT)} ({path.stat().st_size // 1024} kB)")
