#!/usr/bin/env python3
"""Instructions, branches and branch mispredictions per ray, ours against Embree, counted by callgrind.

Usage: tools/ray_instructions.py [options] FRAMELESS SCENE...
       tools/ray_instructions.py [--json] --parse CALLGRIND_OUT

Runs `FRAMELESS bench rays SCENE --opaque --size WxH --reps 1 --threads 1` under
`valgrind --tool=callgrind --branch-sim=yes` (with --cache, also its cache simulation) and divides
what callgrind counted inside each call of ours (`Accel::intersect`, `Accel::occluded`) and of
Embree's (`rtcIntersect1`, `rtcOccluded1`) made by the benchmark by the number of those calls:
the same rays on both sides (ours also traces them once untimed: the same mix, counted twice).

Counts are the same from run to run whatever else the machine does, where timing on a shared
machine moves by 10 % or more (docs/benchmarks.md, sections 30 and 31): a change to the walk is
judged by its instructions here and by its time with tools/ab_bench.py. Valgrind runs AVX2 code,
not AVX-512: build with -DFRAMELESS_ARCH=x86-64-v3 (Embree picks its AVX2 path under valgrind by
itself). Valgrind reports its own cache sizes, so the walk's prefetch policy may differ from the
machine's: --prefetch 0 or 1 pins it (FRAMELESS_PREFETCH).
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

from tool_cli import Failure, OneLineParser, executable

# (key, label, pattern of the called function's name, pattern of ours it is compared with)
CALLS = [
    ("ours_intersect", "ours: Accel::intersect", r"^frameless::Accel::intersect\("),
    ("embree_intersect", "Embree: rtcIntersect1", r"^rtcIntersect1$"),
    ("ours_occluded", "ours: Accel::occluded", r"^frameless::Accel::occluded\("),
    ("embree_occluded", "Embree: rtcOccluded1", r"^rtcOccluded1$"),
]
PAIRS = [("ours_intersect", "embree_intersect"), ("ours_occluded", "embree_occluded")]
BENCH_CALLER = "frameless::bench::"  # calls made by bench rays itself (its loops and Embree's wrapper)
NAMES = {"Ir": "instructions", "Bc": "branches", "Bcm": "mispredicted", "Bi": "indirect jumps",
         "Bim": "ind. mispredicted", "Dr": "data reads", "D1mr": "L1 read misses", "DLmr": "L2 read misses",
         "Dw": "data writes", "D1mw": "L1 write misses", "DLmw": "L2 write misses"}


def parse_callgrind(path):
    """Calls and their inclusive costs, by function of CALLS, from a callgrind output file.

    Only the benchmark's own calls count (callers in frameless::bench): not a walk's calls of
    itself through instances, nor a packet's fallback to single rays, so both sides are counted
    on the bench's rays alone. Each call's cost is what callgrind recorded at the call site:
    everything the call executed, inside Embree's library too."""
    try:
        with open(path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
    except OSError as e:
        raise Failure(f"{path}: {e.strerror}")
    events, positions = None, 1
    names = {}  # compressed function names: "(id)" -> name
    fn = None
    pending = None  # (callee, count) of the last calls= line: the next line is its cost
    callee = ""
    totals = {key: {"calls": 0, "cost": None} for key, _, _ in CALLS}
    patterns = [(key, re.compile(p)) for key, _, p in CALLS]

    def name_of(value):
        m = re.match(r"^\((\d+)\)(?: (.*))?$", value)
        if not m:
            return value
        if m.group(2) is not None:
            names[m.group(1)] = m.group(2)
        return names.get(m.group(1), "")

    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("events:"):
            events = line.split()[1:]
            continue
        if line.startswith("positions:"):
            positions = len(line.split()) - 1
            continue
        if line.startswith("fn="):
            fn = name_of(line[3:])
            continue
        if line.startswith("cfn="):
            callee = name_of(line[4:])
            continue
        if line.startswith("calls="):
            fields = line[6:].split()
            if not fields or not fields[0].isdigit():
                raise Failure(f"{path}:{number}: a calls= line without a count")
            pending = (callee, int(fields[0]))
            continue
        if line[0].isdigit() or line[0] in "+-*":
            if events is None:
                raise Failure(f"{path}:{number}: a cost line before the events: line")
            if pending is None:
                continue  # a function's own cost: only calls are counted
            callee, count = pending
            pending = None
            fields = line.split()[positions:]
            try:
                cost = [int(v) for v in fields] + [0] * (len(events) - len(fields))
            except ValueError:
                raise Failure(f"{path}:{number}: a cost that is not a number")
            for key, pattern in patterns:
                if pattern.search(callee) and fn and BENCH_CALLER in fn:
                    t = totals[key]
                    t["calls"] += count
                    t["cost"] = cost if t["cost"] is None else [a + b for a, b in zip(t["cost"], cost)]
            continue
        # Other header and position lines (fl=, fi=, fe=, ob=, cob=, cfi=, cfl=, summary:,
        # totals:, jump=, jcnd=, ...) carry nothing this report needs.
    if events is None:
        raise Failure(f"{path}: not a callgrind output file (no events: line)")
    return events, totals


def per_call(events, totals):
    out = {}
    for key, label, _ in CALLS:
        t = totals[key]
        if t["calls"] == 0:
            continue
        out[key] = {"label": label, "calls": t["calls"],
                    "per_call": {e: c / t["calls"] for e, c in zip(events, t["cost"])}}
    return out


def report(scene, events, calls):
    lines = [f"{scene}: per call, counted by callgrind"]
    shown = [e for e in events if e in NAMES]
    lines.append(f"{'':26}{'calls':>9}" + "".join(f"{NAMES[e]:>19}" for e in shown))
    for key, label, _ in CALLS:
        if key in calls:
            c = calls[key]
            lines.append(f"{label:26}{c['calls']:>9}" + "".join(f"{c['per_call'][e]:>19.2f}" for e in shown))
    for ours, peer in PAIRS:
        if ours in calls and peer in calls:
            a, b = calls[ours]["per_call"], calls[peer]["per_call"]
            cells = "".join(f"{(a[e] / b[e] if b[e] else float('nan')):>19.3f}" for e in shown)
            lines.append(f"{'ours / Embree':26}{'':>9}{cells}   ({calls[ours]['label'][6:]})")
    return "\n".join(lines)


def l2_cache():
    """This machine's L2 (bytes, ways) as getconf reports it; 1 MiB, 16 ways when it does not."""
    size, ways = 1 << 20, 16
    try:
        out = subprocess.run(["getconf", "-a"], capture_output=True, text=True).stdout
        values = dict(line.split(None, 1) for line in out.splitlines() if len(line.split(None, 1)) == 2)
        size = int(values.get("LEVEL2_CACHE_SIZE", size)) or size
        ways = int(values.get("LEVEL2_CACHE_ASSOC", ways)) or ways
    except (OSError, ValueError):
        pass
    return size, ways


def run_scene(binary, scene, args):
    env = dict(os.environ)
    if args.prefetch in ("0", "1"):
        env["FRAMELESS_PREFETCH"] = args.prefetch
    with tempfile.TemporaryDirectory(prefix="ray_instructions") as tmp:
        out = os.path.join(tmp, "callgrind.out")
        command = ["valgrind", "--tool=callgrind", "--branch-sim=yes", f"--callgrind-out-file={out}"]
        if args.cache:
            # The simulated last level is this machine's L2: a tree of tens of megabytes fits the
            # L3 of a big core, and what a ray waits on is what misses the L2.
            size, ways = l2_cache()
            command += ["--cache-sim=yes", f"--LL={size},{ways},64"]
        command += [binary, "bench", "rays", scene, "--opaque", "--size", args.size, "--reps", "1", "--threads", "1"]
        if sys.stderr.isatty():
            print(f"\rcounting {scene} under callgrind (minutes for a big mesh)...", end="", file=sys.stderr, flush=True)
        try:
            run = subprocess.run(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        finally:
            if sys.stderr.isatty():
                print("\r\033[K", end="", file=sys.stderr, flush=True)
        if run.returncode != 0:
            err = run.stderr.decode("utf-8", "replace")
            if "unhandled instruction" in err or "SIGILL" in err:
                raise Failure(f"{scene}: valgrind met an instruction it does not run (an AVX-512 build?): "
                              "build with -DFRAMELESS_ARCH=x86-64-v3")
            last = [l for l in err.splitlines() if l.strip() and not l.startswith("==")]
            raise Failure(f"{scene}: the run under valgrind failed (exit {run.returncode})"
                          + (f": {last[-1].strip()}" if last else ""))
        events, totals = parse_callgrind(out)
    if totals["ours_intersect"]["calls"] == 0:
        raise Failure(f"{scene}: no call of Accel::intersect counted (the grid, or a build without symbols?)")
    return events, totals


def main():
    p = OneLineParser("ray_instructions", description="Instructions, branches and mispredictions per ray, ours against Embree (callgrind).",
               usage="%(prog)s [options] FRAMELESS SCENE... | %(prog)s [--json] --parse CALLGRIND_OUT")
    p.add_argument("binary", nargs="?", help="the frameless binary (an AVX2 build: valgrind runs no AVX-512)")
    p.add_argument("scenes", nargs="*", help="scenes as bench rays takes them (default: bunny)")
    p.add_argument("--size", default="128x128", help="image size WxH of the rays (default 128x128)")
    p.add_argument("--prefetch", choices=["auto", "0", "1"], default="auto",
                   help="the walk's prefetching: 0 or 1 pins FRAMELESS_PREFETCH (default: the binary's policy)")
    p.add_argument("--cache", action="store_true",
                   help="also callgrind's cache simulation (data reads and writes, L1 misses, and misses of this "
                        "machine's L2 as the simulated last level: 'LL')")
    p.add_argument("--json", action="store_true", help="print JSON instead of the table")
    p.add_argument("--parse", metavar="CALLGRIND_OUT", help="read a callgrind output file instead of running one")
    args = p.parse_args()
    if not re.fullmatch(r"[1-9]\d{0,4}x[1-9]\d{0,4}", args.size):
        p.error(f"--size: '{args.size}' is not WxH")
    runs = []
    try:
        if args.parse:
            if args.binary or args.scenes:
                p.error("--parse takes no binary or scene")
            events, totals = parse_callgrind(args.parse)
            runs.append((args.parse, events, totals))
        else:
            if not args.binary:
                p.error("a frameless binary is needed (or --parse FILE)")
            binary = executable(args.binary)
            if not binary:
                raise Failure(f"{args.binary}: not an executable file")
            if not shutil.which("valgrind"):
                raise Failure("valgrind: not installed (apt-get install valgrind)")
            for scene in args.scenes or ["bunny"]:
                events, totals = run_scene(binary, scene, args)
                runs.append((scene, events, totals))
    except Failure as e:
        print(f"ray_instructions: {e}", file=sys.stderr)
        return 2
    if args.json:
        out = [{"scene": scene, "events": events, "calls": per_call(events, totals)} for scene, events, totals in runs]
        print(json.dumps(out[0] if len(out) == 1 else {"runs": out}))
    else:
        print("\n\n".join(report(scene, events, per_call(events, totals)) for scene, events, totals in runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
