"""`python -m corps`: runs from Python, on corps' simulator or on MuJoCo.

    python -m corps run SCENARIO [--plant corps|mujoco] [--robot R] [--duration S] [--csv FILE]
    python -m corps crossval [--robot talos] [--markdown]
    python -m corps learn CAMPAIGN [--iterations N] [--repeats R] [--seed S] [-o DIR] [--ray ADDRESS]

`run` prints the metrics as `corps run` does (and writes the time series with --csv).
`crossval` runs the same scenarios on both plants and prints the comparison table
(`corps.crossval`). `learn` is `corps learn`, its rollouts optionally on a Ray cluster
(`corps.learn`; also installed as the `corps-learn` command).
"""

import argparse
import sys

import corps

from . import crossval


def make_plant(name, robot, timestep):
    if name == "corps":
        return None
    if name == "mujoco":
        from .mujoco_plant import MujocoPlant

        return MujocoPlant(robot or "talos", timestep=timestep)
    raise SystemExit(f"corps: error: --plant: '{name}' is not one of corps, mujoco")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["learn"]:
        from . import learn

        return learn.main(argv[1:], prog="python -m corps learn")
    p = argparse.ArgumentParser(prog="python -m corps", description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a scenario file")
    r.add_argument("scenario")
    r.add_argument("--plant", default="corps", help="corps (the simulator) or mujoco")
    r.add_argument("--robot", help="replaces the scenario's robot")
    r.add_argument("--duration", type=float, help="controlled time (s)")
    r.add_argument("--timestep", type=float, default=1e-3, help="MuJoCo's step (s)")
    r.add_argument("--csv", help="write the time series here")
    c = sub.add_parser("crossval", help="the same scenarios on corps' simulator and on MuJoCo")
    c.add_argument("--robot", default="talos")
    c.add_argument("--markdown", action="store_true")
    sub.add_parser("learn", help="learn task weights (corps learn), optionally on Ray", add_help=False)
    args = p.parse_args(argv)
    try:
        if args.command == "run":
            robot_for_plant = args.robot
            if args.plant == "mujoco" and robot_for_plant is None:
                robot_for_plant = crossval.scenario_robot(args.scenario)
            plant = make_plant(args.plant, robot_for_plant, args.timestep)
            result = corps.run(args.scenario, robot=args.robot, duration=args.duration, plant=plant)
            print(result.report)
            if args.csv:
                import numpy as np

                np.savetxt(args.csv, result.data, delimiter=",", header=",".join(result.columns),
                           comments="")
            if result.verdict != result.expected:
                print(f"corps: error: the run ended {result.verdict} (the scenario expects "
                      f"{result.expected})", file=sys.stderr)
                return 1
        else:
            crossval.main(args.robot, args.markdown)
    except corps.CorpsError as e:
        print(f"corps: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
