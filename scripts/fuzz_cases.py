#!/usr/bin/python3
"""Mutation fuzzer for fibrane case files (standard library only).

Takes examples/*.yaml, shrinks them so that a run is quick (element counts capped at 4 per direction,
sampling points at 2), applies one to three random text mutations to each mutant (delete, duplicate or swap
lines; replace a number with an extreme value or another type; rename a key; truncate the file; insert
garbage bytes; change an indentation; drop or repeat a list item) and runs `fibrane run MUTANT -q
--threads 1 --max-steps N -o TMP/out` under a time limit and an address-space limit (bash's ulimit -v).

Every fourth mutant runs into an output directory that already holds symbolic links into a sentinel folder
beside it (history.csv, summary.json and a collection, or the vtk/ folder): the sentinel's files must keep
their names and content whatever the exit code (nothing is written or removed through a link).

Exit codes 0 (completed), 1 (stopped: a numerical failure) and 2 (bad input) are fine, provided that an
exit 2 wrote nothing into the output directory. Everything else is a failure: a signal, an abort, a
timeout, any other exit code, or a sanitizer report on stderr. Failing mutants are saved (--keep) and
printed; the script exits 1 if there was any.

  scripts/fuzz_cases.py --binary build/app/fibrane --count 300 --seed 1
"""
import argparse
import concurrent.futures
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

EXTREMES = ["0", "-1", "1e300", "-1e300", "1e-300", "nan", ".nan", ".inf", "-.inf", "2147483647",
            "-2147483648", "9999999999999999999", "1e100", "1e101", "0.5", "3", "100000", "-0.0",
            "abc", "''", '"7"', "[]", "{}", "[1, 2]", "[1e9, 1e9]", "{a: 1}", "true", "null", "~",
            "!!str 5", "*x", "&x 1"]
GARBAGE = [b"\x00", b"\xff\xfe", b"\xc0\xaf", b"\xe9", b"\t", b"\x1b[2J", b"{", b"}", b"[", b"]", b":", b"- ",
           b"---\n", b"...\n", b"&a ", b"*a", b"!!binary ", b"%YAML 1.2\n", b"? ", b"|\n", b">\n", b"#", b"'", b'"',
           b"\\", b"\r", b"\n  - ", b"@", b"`"]
SANITIZER_MARKS = ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:",
                   "terminate called", "Segmentation fault", "stack-overflow")
NUMBER = re.compile(rb"(?<![\w.])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
KEY = re.compile(rb"([A-Za-z_][A-Za-z0-9_]*)(?=:\s)")
SCALAR_VALUE = re.compile(rb"(:\s+)([^\s{}\[\],#][^,}\]\n#]*)")
FLOW_ITEM = re.compile(rb"\[([^\[\]\n]*),([^\[\]\n]*)\]")


def shrink(text):
    """Caps element counts at 4 and sampling points at 2 so that every seed runs in well under a second."""
    def cap_list(m):
        nums = [min(int(float(x)), 4) for x in re.findall(rb"[\d.e+]+", m.group(2))]
        return m.group(1) + b"[" + b", ".join(str(n).encode() for n in nums) + b"]"
    text = re.sub(rb"(elements:\s*)\[([^\]]*)\]", cap_list, text)
    text = re.sub(rb"(elements:\s*)(\d+)", lambda m: m.group(1) + str(min(int(m.group(2)), 4)).encode(), text)
    return re.sub(rb"(samples:\s*)(\d+)", lambda m: m.group(1) + b"2", text)


def lines_of(text):
    return text.split(b"\n")


def mutate_once(rng, text):
    """One random mutation of `text`; returns (new text, description)."""
    lines = lines_of(text)
    kind = rng.choice(["delete", "duplicate", "swap", "number", "number", "number", "scalar", "key",
                       "truncate", "garbage", "indent", "flow"])
    if kind in ("delete", "duplicate", "indent") and lines:
        i = rng.randrange(len(lines))
        if kind == "delete":
            del lines[i]
        elif kind == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines[i] = lines[i][2:] if lines[i].startswith(b"  ") and rng.random() < 0.5 else b"  " + lines[i]
        return b"\n".join(lines), f"{kind} line {i + 1}"
    if kind == "swap" and len(lines) > 1:
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return b"\n".join(lines), f"swap lines {i + 1} and {j + 1}"
    if kind == "number":
        spans = [m.span() for m in NUMBER.finditer(text)]
        if spans:
            a, b = rng.choice(spans)
            value = rng.choice(EXTREMES).encode()
            return text[:a] + value + text[b:], f"number {text[a:b].decode()!r} at byte {a} -> {value.decode()!r}"
    if kind == "scalar":
        spans = [m.span(2) for m in SCALAR_VALUE.finditer(text)]
        if spans:
            a, b = rng.choice(spans)
            value = rng.choice(EXTREMES + ["[x, y]", "{b: [1, {c: 2}]}", "longstring" * 20]).encode()
            return text[:a] + value + text[b:], f"value {text[a:b][:30]!r} at byte {a} -> {value.decode()!r}"
    if kind == "key":
        keys = [m.span(1) for m in KEY.finditer(text)]
        if keys:
            a, b = rng.choice(keys)
            other = rng.choice([text[x:y] for x, y in keys] + [b"nope", text[a:b] + b"s", text[a:b][:-1]])
            return text[:a] + other + text[b:], f"key {text[a:b].decode()!r} at byte {a} -> {other.decode()!r}"
    if kind == "flow":
        spans = [m.span() for m in FLOW_ITEM.finditer(text)]
        if spans:
            a, b = rng.choice(spans)
            inner = text[a + 1:b - 1].split(b",")
            if rng.random() < 0.5:
                del inner[rng.randrange(len(inner))]
            else:
                inner.append(rng.choice(inner))
            return text[:a] + b"[" + b",".join(inner) + b"]" + text[b:], f"list at byte {a} resized"
    if kind == "truncate" and text:
        n = rng.randrange(len(text))
        return text[:n], f"truncate at byte {n}"
    n = rng.randrange(len(text) + 1)
    junk = b"".join(rng.choice(GARBAGE) for _ in range(rng.randint(1, 3)))
    return text[:n] + junk + text[n:], f"insert {junk!r} at byte {n}"


def make_mutant(rng, seeds):
    name, text = rng.choice(seeds)
    steps = []
    for _ in range(rng.choice([1, 1, 2, 3])):
        text, what = mutate_once(rng, text)
        steps.append(what)
    return name, text, steps


def plant_links(folder, out, index):
    """For every fourth mutant: links in `out` into `folder`/sentinel (files, or the vtk/ folder)."""
    if index % 4 != 1:
        return None
    sentinel = os.path.join(folder, "sentinel")
    os.makedirs(sentinel)
    os.makedirs(out)
    names = ["history.csv", "summary.json", "membrane.pvd", "membrane_000000.vtu", "roof_000000.vtu"]
    for n in names:
        with open(os.path.join(sentinel, n), "w") as f:
            f.write(f"sentinel {n}\n")
    if index % 8 == 1:
        os.symlink(sentinel, os.path.join(out, "vtk"))
    else:
        for n in names[:3]:
            os.symlink(os.path.join(sentinel, n), os.path.join(out, n))
    return snapshot(sentinel)


def snapshot(folder):
    """The names and contents of the files in `folder`."""
    result = {}
    for n in sorted(os.listdir(folder)):
        with open(os.path.join(folder, n), "rb") as f:
            result[n] = f.read()
    return result


def run_one(args, index, name, text, steps, work):
    """Runs one mutant in its own directory; returns (status, exit code, seconds, stderr, path)."""
    folder = os.path.join(work, f"m{index:05d}")
    os.makedirs(folder)
    path = os.path.join(folder, f"mutant_{index:05d}.yaml")
    with open(path, "wb") as f:
        f.write(text)
    out = os.path.join(folder, "out")
    planted = plant_links(folder, out, index)
    before = sorted(os.listdir(out)) if planted is not None else []
    limit = f"ulimit -v {args.memory * 1024}; " if args.memory > 0 else ""
    command = (f"{limit}exec '{args.binary}' run '{path}' -q --threads 1 --max-steps {args.max_steps} "
               f"-o '{out}'")
    start = time.monotonic()
    try:
        r = subprocess.run(["bash", "-c", command], cwd=folder, capture_output=True, timeout=args.timeout)
        code, err = r.returncode, r.stdout.decode(errors="replace") + r.stderr.decode(errors="replace")
        status = "ok" if code in (0, 1, 2) else f"exit {code}" if code > 0 else f"signal {-code}"
    except subprocess.TimeoutExpired as e:
        code, err, status = None, (e.stderr or b"").decode(errors="replace"), f"timeout {args.timeout} s"
    seconds = time.monotonic() - start
    if status == "ok" and any(mark in err for mark in SANITIZER_MARKS):
        status = "sanitizer report"
    if status == "ok" and code == 2 and os.path.exists(out) and sorted(os.listdir(out)) != before:
        status = "bad input wrote output"
    if status == "ok" and planted is not None and snapshot(os.path.join(folder, "sentinel")) != planted:
        status = "wrote or removed through a symbolic link"
    if status == "ok":
        shutil.rmtree(folder, ignore_errors=True)
    return status, code, seconds, err, path


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", required=True, help="the fibrane executable")
    p.add_argument("--examples", default=os.path.join(here, "..", "examples"), help="folder of seed cases")
    p.add_argument("--count", type=int, default=300, help="number of mutants")
    p.add_argument("--seed", type=int, default=1, help="random seed (a run is reproducible)")
    p.add_argument("--timeout", type=float, default=20.0, help="seconds per mutant")
    p.add_argument("--memory", type=int, default=4096, help="address-space limit in MiB (0: none, for ASan)")
    p.add_argument("--max-steps", type=int, default=2, help="fibrane run --max-steps")
    p.add_argument("--jobs", type=int, default=2, help="mutants run at once")
    p.add_argument("--keep", default="", help="folder to copy failing mutants into")
    args = p.parse_args()
    args.binary = os.path.abspath(args.binary)

    seeds = []
    for f in sorted(os.listdir(args.examples)):
        if f.endswith(".yaml"):
            with open(os.path.join(args.examples, f), "rb") as fh:
                seeds.append((f, shrink(fh.read())))
    if not seeds:
        sys.exit(f"fuzz_cases: no seed cases in {args.examples}")
    rng = random.Random(args.seed)
    mutants = [make_mutant(rng, seeds) for _ in range(args.count)]
    work = tempfile.mkdtemp(prefix="fibrane-fuzz-")
    start = time.monotonic()
    codes, failures = {}, []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(run_one, args, i, *m, work) for i, m in enumerate(mutants)]
        for i, job in enumerate(jobs):
            status, code, seconds, err, path = job.result()
            codes[code] = codes.get(code, 0) + 1
            if status != "ok":
                name, _, steps = mutants[i]
                failures.append((i, name, steps, status, err, path))
    elapsed = time.monotonic() - start
    for i, name, steps, status, err, path in failures:
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
            shutil.copy(path, args.keep)
        print(f"FAIL mutant {i} of {name} ({'; '.join(steps)}): {status}\n  file: {path}")
        for line in err.strip().splitlines()[-8:]:
            print(f"  | {line}")
    summary = ", ".join(f"exit {c}: {n}" for c, n in sorted(codes.items(), key=lambda kv: str(kv[0])))
    print(f"fuzz_cases: {args.count} mutants of {len(seeds)} examples (seed {args.seed}) in {elapsed:.1f} s; "
          f"{summary}")
    print(f"{args.count - len(failures)} passed, {len(failures)} failed")
    if not failures:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
