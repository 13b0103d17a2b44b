#!/usr/bin/python3
"""Reference timings of SciPy's linear_sum_assignment(maximize=True) on the same
problems as annex-bench's BM_MaxWeightAssignment: dense matrices drawn uniformly
from [0, 100), fixed seed. Prints the median wall and CPU times of several runs
per size.

Run with Debian's interpreter, which has python3-scipy:
    /usr/bin/python3 bench/scipy_assignment.py [--repetitions 9] [--sizes 100x100 2000x2000]
"""

import argparse
import statistics
import sys
import time

try:
    import numpy as np
    from scipy.optimize import linear_sum_assignment
except ImportError as e:  # the python3 first on PATH may lack SciPy
    sys.exit(f"scipy_assignment.py: {e}; run it with /usr/bin/python3 (python3-scipy)")

DEFAULT_SIZES = ["10x10", "100x100", "1000x1000", "2000x2000", "500x2000", "2000x500"]


def parse_size(text):
    rows, cols = text.lower().split("x")
    return int(rows), int(cols)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=DEFAULT_SIZES,
                        help="matrix sizes as ROWSxCOLS (default: %(default)s)")
    parser.add_argument("--repetitions", type=int, default=9,
                        help="timed runs per size; the median is reported")
    parser.add_argument("--seed", type=int, default=42)
    args = parser.parse_args()

    print(f"scipy {__import__('scipy').__version__}, numpy {np.__version__}, "
          f"median of {args.repetitions} runs")
    # Wall time is what annex-bench's "Time" column shows, CPU time its "CPU" column;
    # on a shared machine the CPU time is the steadier of the two.
    print(f"{'size':>12} {'wall_median_ms':>15} {'cpu_median_ms':>14} {'wall_min_ms':>12} "
          f"{'wall_max_ms':>12} {'total':>14}")
    for text in args.sizes:
        rows, cols = parse_size(text)
        rng = np.random.default_rng(args.seed)
        weights = rng.uniform(0.0, 100.0, size=(rows, cols))
        # Small sizes finish in microseconds: time batches so the clock resolves them.
        batch = max(1, int(2e5 // (rows * cols)))
        wall_ms = []
        cpu_ms = []
        total = 0.0
        for _ in range(args.repetitions):
            wall_start = time.perf_counter()
            cpu_start = time.process_time()
            for _ in range(batch):
                r, c = linear_sum_assignment(weights, maximize=True)
            cpu_ms.append((time.process_time() - cpu_start) * 1e3 / batch)
            wall_ms.append((time.perf_counter() - wall_start) * 1e3 / batch)
            total = weights[r, c].sum()
        print(f"{text:>12} {statistics.median(wall_ms):15.3f} {statistics.median(cpu_ms):14.3f} "
              f"{min(wall_ms):12.3f} {max(wall_ms):12.3f} {total:14.4f}")


if __name__ == "__main__":
    main()
