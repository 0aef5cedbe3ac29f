"""Run every benchmarks/bench_*.py (each has a main()) and print their results."""

import importlib.util
import os
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
only = sys.argv[1:]
for name in sorted(os.listdir(here)):
    if not (name.startswith("bench_") and name.endswith(".py")):
        continue
    if only and not any(o in name for o in only):
        continue
    spec = importlib.util.spec_from_file_location(name[:-3], os.path.join(here, name))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    print(f"==== {name}")
    t0 = time.perf_counter()
    mod.main()
    print(f"==== {name}: {time.perf_counter() - t0:.1f} s\n")
