"""The protocol of a plant written in Python (another physics engine, a robot bridge).

`corps.run(scenario, plant=obj)` runs the scenario's controller and estimator on `obj` in
place of corps' simulator: the robot first settles in corps' simulator, then `obj.reset` gets
that state and the loop calls `obj.step(command)` once per control period and `obj.state()`
after each step. corps reads the robot's sensors (encoders, joint torques, F/T sensors, IMU)
from the reported state with the scenario's sensor noise, so the controller sees the same kind
of readings whatever computes the physics. Subclassing is optional: any object with these three
methods works. An exception raised in a method ends the run and is re-raised by `corps.run`.
"""

from typing import Any, Dict

import numpy as np


class Plant:
    """Base class documenting the plant protocol (Pinocchio's q and v conventions).

    A plant that takes position or velocity commands also defines `servo(kp, kd, ki)`: the
    scenario's joint servo gains (per actuated joint; `ki` None without an integral term),
    given once after `reset`, for corps' PD law τ = kp (q_ref − q) + kd (v_ref − v).

    A plant that can push the robot also defines
    `push(frame, start, duration, force, torque)`: the scenario's pushes, `force` (N, world
    axes) at the origin of `frame` and `torque` (N·m, world axes) from time `start` for
    `duration` seconds on the plant's clock, each given once after `reset`. A scenario with
    pushes does not run on a plant without it."""

    def reset(self, q: np.ndarray, v: np.ndarray, t: float, dt: float) -> None:
        """Start from configuration q (size nq) and velocity v (size nv) at time t (s);
        every `step` lasts dt seconds (the control period)."""
        raise NotImplementedError

    def step(self, command: Any) -> None:
        """Apply `command` (a `corps.Command`) for one control period.

        command.kind is "torque" (command.torque: joint torques, N·m, size na = nv - 6),
        "position" (command.q_ref: a full configuration whose joint part is the target,
        command.v_ref: joint velocity targets, size na) or "velocity" (command.v_ref)."""
        raise NotImplementedError

    def state(self) -> Dict[str, Any]:
        """The true state now, as a dict:

        - "t": time (s);
        - "q": configuration (size nq), "v": velocity (size nv; base twist in the base frame);
        - "tau" (optional): joint torques applied over the last period (size na or nv);
        - "contacts" (optional): a (k, 7) array of rows [joint, px, py, pz, fx, fy, fz], the
          force (N) at point p (m) on the body of moving joint `joint` (an index into
          model.joint_names), world frame. The F/T sensors read these."""
        raise NotImplementedError
