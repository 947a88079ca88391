"""The same scenarios on corps' simulator and on MuJoCo, side by side (`python -m corps
crossval`): TALOS's foot force split standing, the base's excursion and recovery after a
100 N × 0.1 s push and the push that fells it, the 20 cm walk's ZMP and CoM errors (all under
the TSID torque controller, through the same estimator and sensors), and iCub stepping in
place under seed 001's soft-tasks controller (S2). MuJoCo runs twice: with its default
contact, and with its contact made as stiff as corps-sim's (`mujoco_plant.STIFF`). Rows where
default MuJoCo differs from corps-sim by more than 20% are flagged; the diagnostic rows (sole
height under the weight, foot slip, the estimator's drift, the errors with the exact state
fed) are what tells the contact models apart.

Run from the repository root (the scenarios are read from `scenarios/`).
"""

import pathlib
import tempfile
import time
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

import corps

STAND = "scenarios/control/tsid_torque_stand.toml"
PUSH = "scenarios/control/tsid_torque_push_front.toml"
WALK = "scenarios/walk/tsid_torque_20cm.toml"
STEP = "scenarios/icub/fsm2_stepping.toml"
FLAG = 0.20
PLANTS = ("corps-sim", "MuJoCo", "MuJoCo stiff")

Row = Tuple[str, List[float]]


def scenario_robot(path: str) -> str:
    """The robot a scenario file names (TALOS when it names none, as corps does)."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        import tomli as tomllib
    robot = tomllib.loads(pathlib.Path(path).read_text()).get("robot", {})
    return robot.get("description", "talos")


def plant_factories(robot: str) -> List[Callable[[], Optional["corps.Plant"]]]:
    from .mujoco_plant import STIFF, MujocoPlant

    return [lambda: None, lambda: MujocoPlant(robot), lambda: MujocoPlant(robot, **STIFF)]


class Timed:
    """A run's result with its wall time (s)."""

    def __init__(self, result, wall):
        self.result, self.wall = result, wall

    def __getattr__(self, name):
        return getattr(self.result, name)

    def __getitem__(self, column):
        return self.result[column]

    def __len__(self):
        return len(self.result)


def runs(path: str, robot: str, **options) -> List[Timed]:
    """The scenario on each plant, timed."""
    if not pathlib.Path(path).exists():
        raise corps.ScenarioError(f"{path}: no such scenario file (run from the repository root)")
    out = []
    for make in plant_factories(robot):
        start = time.perf_counter()
        result = corps.run(path, robot=robot, plant=make(), **options)
        out.append(Timed(result, time.perf_counter() - start))
    return out


def per_plant(results, f) -> List[float]:
    return [float(f(r)) for r in results]


def standing(robot: str) -> List[Row]:
    rs = runs(STAND, robot, duration=3.0)

    def late(r, column):
        return r[column][r["t"] >= r["t"][-1] - 1.0].mean()

    return [
        ("standing: left foot force (N)", per_plant(rs, lambda r: late(r, "left_foot_fz"))),
        ("standing: right foot force (N)", per_plant(rs, lambda r: late(r, "right_foot_fz"))),
        ("standing: left share of the weight (%)", per_plant(rs, lambda r: 100 * late(r, "left_foot_fz") / (
            late(r, "left_foot_fz") + late(r, "right_foot_fz")))),
        ("diagnostic: sole frame height under the weight (mm; lower: softer)",
         per_plant(rs, lambda r: 500 * (late(r, "left_foot_z") + late(r, "right_foot_z")))),
    ]


def push_figures(r) -> Dict[str, float]:
    t, x = r["t"], r["base_x"]
    before = (t > 0.5) & (t < 1.0)
    after = t >= 1.0
    excursion = np.abs(x[after] - x[before].mean())
    k = int(np.argmax(excursion))
    outside = np.nonzero(excursion > 0.1 * excursion[k])[0]
    lift = max(r[c][after].max() - r[c][before].mean() for c in ("left_foot_z", "right_foot_z"))
    return {"peak": excursion[k], "t_peak": t[after][k] - 1.0,
            "back": t[after][outside[-1]] - 1.0 if len(outside) else 0.0,
            "end": excursion[-1], "lift": lift}


def fall_threshold(robot: str, make, forces=range(150, 476, 25)) -> float:
    """The smallest push (N, 0.1 s at the pelvis, from the front) in `forces` that the robot
    does not withstand (the run ends otherwise than completed: fell, or diverged on hitting
    the floor) on the plant `make()` gives; inf if it withstands all."""
    text = pathlib.Path(PUSH).read_text()
    if "force = [100.0, 0.0, 0.0]" not in text:
        raise corps.ScenarioError(f"{PUSH}: the push sweep expects its 100 N push")
    with tempfile.TemporaryDirectory() as tmp:
        for force in forces:
            path = pathlib.Path(tmp) / f"push_{force}.toml"
            path.write_text(text.replace("force = [100.0, 0.0, 0.0]", f"force = [{force}.0, 0.0, 0.0]"))
            if corps.run(str(path), robot=robot, plant=make()).verdict != "completed":
                return float(force)
    return float("inf")


def push_scale(robot: str) -> float:
    """What the push scenario's forces are multiplied by on `robot` (its `for_mass`)."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        import tomli as tomllib
    pushes = tomllib.loads(pathlib.Path(PUSH).read_text()).get("push", [])
    for_mass = pushes[0].get("for_mass") if pushes else None
    return corps.Model.from_robot(robot).total_mass() / for_mass if for_mass else 1.0


def push(robot: str) -> List[Row]:
    figures = [push_figures(r) for r in runs(PUSH, robot)]
    scale = push_scale(robot)
    return [
        (f"push {100 * scale:.0f} N × 0.1 s: base excursion peak (mm)", [1e3 * f["peak"] for f in figures]),
        ("push: time of the peak after the push (s)", [f["t_peak"] for f in figures]),
        ("push: back within 10% of the peak after (s)", [f["back"] for f in figures]),
        ("push: base offset at the end (mm)", [1e3 * f["end"] for f in figures]),
        ("diagnostic: peak sole lift during the push (mm)", [1e3 * f["lift"] for f in figures]),
        ("push sweep (25 N steps on TALOS, 0.1 s): smallest push not withstood (N)",
         [scale * fall_threshold(robot, make) for make in plant_factories(robot)]),
    ]


def walk(robot: str) -> List[Row]:
    rs = runs(WALK, robot)
    rows: List[Row] = []
    for name, key, axes in (("ZMP", "zmp_error", "xy"), ("CoM", "com_error", "xyz")):
        for k, axis in enumerate(axes):
            for stat in ("avg", "peak"):
                rows.append((f"20 cm walk: {name} error {axis} {stat} (mm)",
                             per_plant(rs, lambda r: 1e3 * r.metrics[key][k][stat])))
    rows.append(("20 cm walk: distance travelled (m)",
                 per_plant(rs, lambda r: (r.metrics.get("walk") or {}).get("distance", np.nan))))

    def zmp_x_peak_after(r, t0=0.1):
        late = r["t"] >= t0
        return 1e3 * np.max(np.abs(r["zmp_x"][late] - r["zmp_ref_x"][late]))

    rows.append(("diagnostic: ZMP error x peak after the first 0.1 s (mm)", per_plant(rs, zmp_x_peak_after)))
    rows.append(("diagnostic: foot slip over the walk (mm)",
                 per_plant(rs, lambda r: 1e3 * max(f["slip"] for f in r.metrics["feet"]))))
    rows.append(("diagnostic: foot z error peak (mm)",
                 per_plant(rs, lambda r: 1e3 * max(f["error"][2]["peak"] for f in r.metrics["feet"]))))
    rows.append(("diagnostic: estimator CoM z drift at the end (mm)",
                 per_plant(rs, lambda r: 1e3 * (r["com_est_z"][-1] - r["com_z"][-1]))))
    exact = runs(WALK, robot, estimator="ground-truth")
    for k, axis in enumerate("xyz"):
        rows.append((f"diagnostic: CoM error {axis} avg, exact state fed (mm)",
                     per_plant(exact, lambda r: 1e3 * r.metrics["com_error"][k]["avg"])))
    rows.append(("cost: wall time per control tick, whole run (µs)",
                 per_plant(rs, lambda r: 1e6 * r.wall / len(r))))
    return rows


def stepping() -> List[Row]:
    """iCub stepping in place under seed 001's soft-tasks controller (S2), 60 s."""
    rs = runs(STEP, "icub", duration=60.0)

    def strides(r):
        line = next(x for x in r.report.splitlines() if x.strip().startswith("strides"))
        return float(line.split(":")[1].split()[0])

    rows = [("iCub S2 60 s: strides", per_plant(rs, strides))]
    for k, axis in enumerate("xyz"):
        rows.append((f"iCub S2: CoM error {axis} peak (mm)",
                     per_plant(rs, lambda r: 1e3 * r.metrics["com_error"][k]["peak"])))
    rows.append(("iCub S2: foot slip (mm)",
                 per_plant(rs, lambda r: 1e3 * max(f["slip"] for f in r.metrics["feet"]))))
    rows.append(("iCub S2: verdicts completed (of 1)", per_plant(rs, lambda r: r.verdict == "completed")))
    return rows


def table(robot: str) -> List[Row]:
    return standing(robot) + push(robot) + walk(robot) + stepping()


def main(robot: str = "talos", markdown: bool = False) -> None:
    import mujoco

    rows = table(robot)
    head = [f"{robot}: quantity", PLANTS[0], f"{PLANTS[1]} {mujoco.__version__}", PLANTS[2],
            "MuJoCo/corps", "stiff/corps", "differs > 20%"]
    if markdown:
        print("| " + " | ".join(head) + " |")
        print("|---|---:|---:|---:|---:|---:|---|")
    for label, values in rows:
        a = values[0]
        ratios = [v / a if a != 0 and np.isfinite(a) else np.nan for v in values[1:]]
        flag = "yes" if np.isfinite(ratios[0]) and abs(ratios[0] - 1.0) > FLAG else ""
        cells = [f"{v:.3g}" for v in values] + [f"{x:.2f}" for x in ratios]
        if markdown:
            print(f"| {label} | " + " | ".join(cells) + f" | {flag} |")
        else:
            print(f"{label:<62} " + "  ".join(f"{c:>9}" for c in cells) + (" *" if flag else ""))
