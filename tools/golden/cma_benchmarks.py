"""pycma's results on the benchmark problems of crates/corps-learn/tests/benchmarks.rs, for
that test to compare corps' (1+1)-CMA-ES with: the best value found and the evaluations
pycma's CMA-ES (unconstrained: cma.fmin2; constrained: cma.fmin_con2, its augmented-Lagrangian
constraint handling) used, over 5 seeds each, from the same start points and step sizes.

The problems (minimization, g(x) <= 0 feasible):
- sphere10: sum x_i^2, n = 10, x0 = 1, sigma0 = 1; optimum 0.
- rosenbrock10: sum 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2, n = 10, x0 = 0, sigma0 = 0.5; optimum 0.
- sphere_linear10: sum x_i^2 s.t. 1 - x_0 <= 0, n = 10, x0 = 3, sigma0 = 1; optimum 1 at e_0
  (Arnold & Hansen 2012's linearly constrained sphere).
- tr2: x1^2 + x2^2 s.t. 2 - x1 - x2 <= 0, x0 = (3, 3), sigma0 = 1; optimum 2 at (1, 1).
- g06: (x1 - 10)^3 + (x2 - 20)^3 s.t. 100 - (x1-5)^2 - (x2-5)^2 <= 0,
  (x1-6)^2 + (x2-5)^2 - 82.81 <= 0, 13 <= x1 <= 100, 0 <= x2 <= 100, x0 = (15.05, 5) (feasible:
  the (1+1) strategy starts from a feasible point), sigma0 = 1;
  optimum -6961.81387558 at (14.095, 0.84296) (CEC 2006 problem g06).

Usage: pip install cma numpy; python3 tools/golden/cma_benchmarks.py
Writes crates/corps-learn/tests/data/pycma_benchmarks.json.
"""
import json
from pathlib import Path

import cma
import numpy as np


def sphere(x):
    return float(np.sum(np.asarray(x) ** 2))


def rosenbrock(x):
    x = np.asarray(x)
    return float(np.sum(100 * (x[1:] - x[:-1] ** 2) ** 2 + (1 - x[:-1]) ** 2))


def g06(x):
    return float((x[0] - 10) ** 3 + (x[1] - 20) ** 3)


def g06_constraints(x):
    return [
        100 - (x[0] - 5) ** 2 - (x[1] - 5) ** 2,
        (x[0] - 6) ** 2 + (x[1] - 5) ** 2 - 82.81,
        13 - x[0], x[0] - 100, -x[1], x[1] - 100,
    ]


PROBLEMS = {
    "sphere10": (sphere, None, [1.0] * 10, 1.0, 0.0),
    "rosenbrock10": (rosenbrock, None, [0.0] * 10, 0.5, 0.0),
    "sphere_linear10": (sphere, lambda x: [1 - x[0]], [3.0] * 10, 1.0, 1.0),
    "tr2": (sphere, lambda x: [2 - x[0] - x[1]], [3.0, 3.0], 1.0, 2.0),
    "g06": (g06, g06_constraints, [15.05, 5.0], 1.0, -6961.81387558),
}

out = {"pycma_version": cma.__version__, "problems": {}}
for name, (f, g, x0, sigma0, optimum) in PROBLEMS.items():
    runs = []
    for seed in range(1, 6):
        opts = {"seed": seed, "verbose": -9, "tolfun": 1e-12, "tolx": 1e-12, "maxfevals": 200000}
        if g is None:
            x, es = cma.fmin2(f, x0, sigma0, opts)
            best, evals = float(es.result.fbest), int(es.result.evaluations)
        else:
            x, es = cma.fmin_con2(f, x0, sigma0, constraints=g, options=opts)
            best, evals = float(f(x)), int(es.result.evaluations)
            assert max(g(x)) <= 1e-6, (name, g(x))
        runs.append({"seed": seed, "best": best, "evaluations": evals, "x": [float(v) for v in x]})
    out["problems"][name] = {"optimum": optimum, "x0": x0, "sigma0": sigma0, "runs": runs}
    print(name, [round(r["best"], 8) for r in runs], [r["evaluations"] for r in runs])

path = Path(__file__).resolve().parents[2] / "crates/corps-learn/tests/data/pycma_benchmarks.json"
path.write_text(json.dumps(out, indent=1) + "\n")
print("wrote", path)
