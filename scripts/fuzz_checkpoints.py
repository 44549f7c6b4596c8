#!/usr/bin/python3
"""Mutation fuzzer for fibrane's restart input: checkpoint.bin and history.csv (standard library only).

Runs the shallow-roof example by load stepping (t to 0.5 in 6 steps, --threads 1) stopped by --max-steps 3,
restarts an undamaged copy of the stopped run, then damages copies of the stopped run's directory and
restarts each under a time limit and an address-space limit: random bit flips, truncations, appended bytes,
duplicated ranges, entry lengths, name lengths and the entry count patched to random values (half of those
with the checksum recomputed, as a forger would, so that the parser's own bounds are exercised), and
history.csv rows edited, removed, inserted or appended.

Each mutant must end with exit code 2, a message ("fibrane: error: ...") naming checkpoint.bin or
history.csv, and the directory's files unchanged; or with exit code 0 and a history.csv bit-identical to
the undamaged restart's. Anything else fails: a signal, an abort, a time-out, exit code 1, a different
history with exit code 0, or a sanitizer report. The script exits 1 if any mutant failed.

  scripts/fuzz_checkpoints.py --binary build/app/fibrane --count 120 --seed 1
"""
import argparse
import concurrent.futures
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time

SANITIZER_MARKS = ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:",
                   "terminate called", "Segmentation fault", "stack-overflow")
MAGIC_SIZE = len(b"FIBRANE-CHECKPOINT 2\n")


def fnv1a64(data):
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def reseal(data):
    return data[:-8] + struct.pack("<Q", fnv1a64(data[:-8]))


def fields(data):
    """Offsets of the length fields of an undamaged checkpoint: [(offset, size in bytes, value)]."""
    out = [(MAGIC_SIZE, 8, struct.unpack_from("<Q", data, MAGIC_SIZE)[0])]
    pos = MAGIC_SIZE + 8
    for _ in range(out[0][2]):
        kind = data[pos]
        name_size = struct.unpack_from("<I", data, pos + 1)[0]
        out.append((pos + 1, 4, name_size))
        count_at = pos + 5 + name_size
        count = struct.unpack_from("<Q", data, count_at)[0]
        out.append((count_at, 8, count))
        pos = count_at + 8 + count * (8 if kind == 0 else 1)
    return out


def mutate_checkpoint(rng, data, length_fields):
    kind = rng.choice(["flip", "flip", "truncate", "append", "duplicate", "length", "length", "length"])
    if kind == "flip":
        data = bytearray(data)
        where = [rng.randrange(len(data)) for _ in range(rng.randint(1, 3))]
        for at in where:
            data[at] ^= 1 << rng.randrange(8)
        return bytes(data), f"bits flipped at {where}"
    if kind == "truncate":
        n = rng.randrange(len(data))
        return data[:n], f"truncated to {n} bytes"
    if kind == "append":
        junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
        return data + junk, f"{len(junk)} bytes appended"
    if kind == "duplicate":
        a = rng.randrange(len(data))
        b = min(len(data), a + rng.randint(1, 256))
        return data[:b] + data[a:b] + data[b:], f"bytes {a}-{b} duplicated"
    at, size, old = rng.choice(length_fields)
    limit = (1 << (8 * size)) - 1
    value = rng.choice([0, 1, max(old - 1, 0), old + 1, old * 2, 1 << rng.randrange(8 * size), limit,
                        rng.randrange(limit + 1)])
    data = data[:at] + value.to_bytes(size, "little") + data[at + size:]
    sealed = rng.random() < 0.5
    return (reseal(data) if sealed else data), f"length at {at} {old} -> {value}{' (resealed)' if sealed else ''}"


def mutate_history(rng, text, vouched_rows):
    lines = text.split(b"\n")[:-1]
    kind = rng.choice(["edit", "delete", "insert", "append"])
    if kind == "append":
        junk = rng.choice([b"1,2,3", b"garbage", b"", b"\x00\xff", b",".join([b"7"] * 11)])
        return text + junk + b"\n", "row appended"
    i = rng.randrange(vouched_rows + 1)  # the header or a vouched row
    if kind == "edit" and lines[i]:
        line = bytearray(lines[i])
        line[rng.randrange(len(line))] = rng.choice(b"0123456789.,-e")
        lines[i] = bytes(line)
    elif kind == "delete":
        del lines[i]
    else:
        lines.insert(i, rng.choice([b"1,2,3", lines[i], b""]))
    return b"\n".join(lines) + b"\n", f"history line {i + 1}: {kind}"


def run_restart(args, case_file, out):
    limit = f"ulimit -v {args.memory * 1024}; " if args.memory > 0 else ""
    command = f"{limit}exec '{args.binary}' run '{case_file}' -q --threads 1 --restart '{out}'"
    try:
        r = subprocess.run(["bash", "-c", command], capture_output=True, timeout=args.timeout)
        return r.returncode, r.stdout.decode(errors="replace") + r.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return None, f"timeout {args.timeout} s"


def snapshot(out):
    files = {}
    for name in ("checkpoint.bin", "history.csv", "summary.json"):
        path = os.path.join(out, name)
        files[name] = open(path, "rb").read() if os.path.isfile(path) else None
    return files


def run_one(args, index, mutant, setup):
    """Restarts one damaged copy; returns (status, exit code, output, folder)."""
    target, data, what = mutant
    folder = os.path.join(setup["work"], f"m{index:05d}")
    shutil.copytree(setup["part"], folder)
    with open(os.path.join(folder, target), "wb") as f:
        f.write(data)
    before = snapshot(folder)
    code, output = run_restart(args, setup["case"], folder)
    if code is None:
        status = output
    elif any(mark in output for mark in SANITIZER_MARKS):
        status = "sanitizer report"
    elif code == 2:
        named = any(f"{os.path.join(folder, n)}:" in output for n in ("checkpoint.bin", "history.csv"))
        status = ("ok" if "fibrane: error:" in output and named else "exit 2 without a message naming the file")
        if status == "ok" and snapshot(folder) != before:
            status = "refused restart changed the directory"
    elif code == 0:
        same = snapshot(folder)["history.csv"] == setup["history"]
        status = "ok" if same else "exit 0 with a history that differs from the undamaged restart's"
    else:
        status = f"exit {code}" if code > 0 else f"signal {-code}"
    if status == "ok":
        shutil.rmtree(folder, ignore_errors=True)
    return status, code, output, folder


def prepare(args, work):
    """The case, the stopped run and the undamaged restart's history."""
    with open(os.path.join(args.examples, "shallow-roof.yaml"), "rb") as f:
        text = f.read()
    case = os.path.join(work, "case.yaml")
    with open(case, "wb") as f:
        f.write(text[:text.index(b"steps:")] + b"steps: {t_end: 0.5, dt: 0.05}\n"
                b"output: {directory: out, vtk: true, vtk_every: 2, checkpoint_every: 2}\n")
    part = os.path.join(work, "part")
    base = [args.binary, "run", case, "-q", "--threads", "1"]
    r = subprocess.run(base + ["-o", part, "--max-steps", "3"], capture_output=True)
    if r.returncode != 1 or not os.path.isfile(os.path.join(part, "checkpoint.bin")):
        sys.exit(f"fuzz_checkpoints: the stopped run failed (exit {r.returncode}): {r.stderr.decode()}")
    clean = os.path.join(work, "clean")
    shutil.copytree(part, clean)
    r = subprocess.run(base + ["--restart", clean], capture_output=True)
    if r.returncode != 0:
        sys.exit(f"fuzz_checkpoints: the undamaged restart failed (exit {r.returncode}): {r.stderr.decode()}")
    with open(os.path.join(clean, "history.csv"), "rb") as f:
        history = f.read()
    return {"work": work, "case": case, "part": part, "history": history}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", required=True, help="the fibrane executable")
    p.add_argument("--examples", default=os.path.join(here, "..", "examples"), help="folder with shallow-roof.yaml")
    p.add_argument("--count", type=int, default=120, help="number of mutants")
    p.add_argument("--seed", type=int, default=1, help="random seed (a run is reproducible)")
    p.add_argument("--timeout", type=float, default=20.0, help="seconds per mutant")
    p.add_argument("--memory", type=int, default=4096, help="address-space limit in MiB (0: none, for ASan)")
    p.add_argument("--jobs", type=int, default=2, help="mutants run at once")
    args = p.parse_args()
    args.binary = os.path.abspath(args.binary)

    work = tempfile.mkdtemp(prefix="fibrane-fuzz-checkpoints-")
    start = time.monotonic()
    setup = prepare(args, work)
    with open(os.path.join(setup["part"], "checkpoint.bin"), "rb") as f:
        checkpoint = f.read()
    with open(os.path.join(setup["part"], "history.csv"), "rb") as f:
        history = f.read()
    length_fields = fields(checkpoint)
    vouched = history.count(b"\n") - 1
    rng = random.Random(args.seed)
    mutants = []
    for _ in range(args.count):
        if rng.random() < 0.8:
            data, what = mutate_checkpoint(rng, checkpoint, length_fields)
            mutants.append(("checkpoint.bin", data, what))
        else:
            data, what = mutate_history(rng, history, vouched)
            mutants.append(("history.csv", data, what))
    codes, failures = {}, []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(run_one, args, i, m, setup) for i, m in enumerate(mutants)]
        for i, job in enumerate(jobs):
            status, code, output, folder = job.result()
            codes[code] = codes.get(code, 0) + 1
            if status != "ok":
                failures.append((i, mutants[i][0], mutants[i][2], status, output, folder))
    elapsed = time.monotonic() - start
    for i, target, what, status, output, folder in failures:
        print(f"FAIL mutant {i} ({target}: {what}): {status}\n  directory: {folder}")
        for line in output.strip().splitlines()[-8:]:
            print(f"  | {line}")
    summary = ", ".join(f"exit {c}: {n}" for c, n in sorted(codes.items(), key=lambda kv: str(kv[0])))
    print(f"fuzz_checkpoints: {args.count} mutants (seed {args.seed}) in {elapsed:.1f} s; {summary}")
    print(f"{args.count - len(failures)} passed, {len(failures)} failed")
    if not failures:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
