#!/usr/bin/env python3
"""Compare two frameless builds (or one build under two environments) on one benchmark.

Usage: tools/ab_bench.py [options] A B -- BENCH ARGS...

Runs `A BENCH ARGS --json` and `B BENCH ARGS --json` alternately, A B B A A B ..., for --rounds
rounds, so that a shared machine's slow and fast spells fall on both sides alike, and prints for
each figure the median of each side, the ratio B / A, in how many rounds B's figure was the
higher, and p: the two-sided sign test's chance of a split at least that uneven if A and B were
alike (rounds where they tie left out; 6 of 6 gives 0.031, 5 of 6 0.22). One run's figure on a
shared machine moves by 10 % or more; a change of a few percent shows only in the medians and the
count over several rounds (docs/benchmarks.md, sections 30 and 32).

Figures are the JSON's numbers, named by their path (embree.ratio_primary_vs_intersect1_1t,
curve_order.phases_ms.splat); --field picks them, --preset names a usual set, and without either
every number whose name has "ratio" in it is shown (every number when none has).
"""
import json
import math
import os
import statistics
import subprocess
import sys

from tool_cli import Failure, OneLineParser, executable

PRESETS = {
    # bench rays: ours against Embree, one thread, by kind of ray.
    "rays": ["embree.ratio_primary_vs_intersect1_1t", "embree.ratio_primary_packet_vs_packet8_1t",
             "embree.ratio_shadow_vs_occluded1_1t", "embree.ratio_bounce_vs_intersect1_1t",
             "embree.ratio_bounce_shadow_vs_occluded1_1t"],
    # bench reproject --order curve: a change and its phases, milliseconds.
    "reproject": ["curve_order.median_ms", "curve_order.phases_ms.splat", "curve_order.phases_ms.cracks",
                  "curve_order.phases_ms.disocclusions", "curve_order.phases_ms.pixel_pass",
                  "curve_order.phases_ms.slot_pass"],
}


def numbers(tree, prefix=""):
    """Every number in a JSON tree, by its dotted path (lists by index)."""
    if isinstance(tree, bool):
        return {}
    if isinstance(tree, (int, float)):
        return {prefix: float(tree)}
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) if isinstance(tree, list) else []
    out = {}
    for key, value in items:
        out.update(numbers(value, f"{prefix}.{key}" if prefix else str(key)))
    return out


def parse_env(pairs, side):
    env = dict(os.environ)
    for pair in pairs:
        name, eq, value = pair.partition("=")
        if not eq or not name:
            raise Failure(f"--env-{side}: expected NAME=VALUE, got '{pair}'")
        env[name] = value
    return env


def run(binary, args, env, side, round_):
    try:
        done = subprocess.run([binary] + args + ["--json"], env=env, capture_output=True)
    except OSError as e:
        raise Failure(f"{side} ({binary}): cannot run: {e.strerror}")
    out = done.stdout.decode("utf-8", errors="replace")
    if done.returncode != 0:
        lines = (done.stderr.decode("utf-8", errors="replace") or out).strip().splitlines()
        raise Failure(f"{side} ({binary}) exited {done.returncode} in round {round_}: {lines[-1] if lines else 'no message'}")
    try:
        return numbers(json.loads(out))
    except ValueError as e:
        line = f" (line {e.lineno}: {e.msg})" if isinstance(e, json.JSONDecodeError) else ""
        raise Failure(f"{side} ({binary}): its output in round {round_} is not JSON{line}")


def sign_test_p(higher, lower):
    """Two-sided sign test: the chance, if each round were a fair coin, of a split of higher and
    lower rounds at least this uneven (ties are no evidence either way and are left out)."""
    n = higher + lower
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, i) for i in range(min(higher, lower) + 1)) / 2 ** n
    return min(1.0, 2.0 * tail)


def clear_progress(progress):
    if progress:
        print("\r" + " " * 30 + "\r", end="", file=sys.stderr, flush=True)


def main(argv):
    if "--" in argv:
        split = argv.index("--")
        own, bench = argv[:split], argv[split + 1:]
    else:
        own, bench = argv, []
    p = OneLineParser("ab_bench", prog="ab_bench.py", usage="%(prog)s [options] A B -- BENCH ARGS...", description=__doc__.split("\n\n")[0],
                                epilog="Example: tools/ab_bench.py --preset rays old/frameless new/frameless "
                                       "-- bench rays bunny --threads 1 --reps 2")
    p.add_argument("a", metavar="A", help="the first frameless binary")
    p.add_argument("b", metavar="B", help="the second (may be A again, with --env-a or --env-b)")
    p.add_argument("--rounds", type=int, default=5, help="rounds, each one run of A and one of B (default 5)")
    p.add_argument("--field", action="append", default=[], help="a figure's JSON path (repeatable)")
    p.add_argument("--preset", choices=sorted(PRESETS), help="a usual set of figures")
    p.add_argument("--env-a", action="append", default=[], metavar="NAME=VALUE", help="environment of A's runs")
    p.add_argument("--env-b", action="append", default=[], metavar="NAME=VALUE", help="environment of B's runs")
    o = p.parse_args(own)
    progress = sys.stderr.isatty()
    try:
        if not bench:
            raise Failure("no benchmark given: put its arguments after --, e.g. -- bench rays bunny")
        if not 1 <= o.rounds <= 1000:
            raise Failure(f"--rounds: must be 1..1000, got {o.rounds}")
        binaries = {}
        for side, binary in (("A", o.a), ("B", o.b)):
            found = executable(binary)
            if not found:
                raise Failure(f"{side}: {binary}: no such executable")
            binaries[side] = found
        envs = {"A": parse_env(o.env_a, "a"), "B": parse_env(o.env_b, "b")}
        fields = list(o.field) + (PRESETS[o.preset] if o.preset else [])
        got = {"A": [], "B": []}
        for r in range(o.rounds):
            for side in ("A", "B") if r % 2 == 0 else ("B", "A"):
                if progress:
                    print(f"\rround {r + 1}/{o.rounds}, {side}  ", end="", file=sys.stderr, flush=True)
                got[side].append(run(binaries[side], bench, envs[side], side, r + 1))
        clear_progress(progress)
        if not fields:
            shared = [k for k in got["A"][0] if k in got["B"][0]]
            fields = [k for k in shared if "ratio" in k.rsplit(".", 1)[-1]] or shared
            if not fields:
                raise Failure("A's and B's outputs share no number to compare")
        # Every round's: a figure the benchmark leaves out (a rate over no rays is written as null)
        # is missing in that round only.
        for f in fields:
            for side in ("A", "B"):
                for r, figures in enumerate(got[side]):
                    if f not in figures:
                        raise Failure(f"{side}'s output has no number '{f}'" + (f" in round {r + 1}" if r else ""))
    except Failure as e:
        clear_progress(progress)
        print(f"ab_bench: {e}", file=sys.stderr)
        return 2
    width = max(len(f) for f in fields)
    print(f"{'figure':<{width}}  {'A median':>10}  {'B median':>10}  {'B / A':>7}  B higher  {'p':>5}")
    for f in fields:
        a = [run_[f] for run_ in got["A"]]
        b = [run_[f] for run_ in got["B"]]
        ma, mb = statistics.median(a), statistics.median(b)
        ratio = f"{mb / ma:7.3f}" if ma else f"{'-':>7}"
        higher = sum(y > x for x, y in zip(a, b))
        lower = sum(y < x for x, y in zip(a, b))
        count = f"{higher} of {o.rounds}"
        print(f"{f:<{width}}  {ma:10.4g}  {mb:10.4g}  {ratio}  {count:<8}  {sign_test_p(higher, lower):5.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
