"""A plant written in Python drives a scenario run: a small penalty-contact simulator built on
corps' own ABA (explicit substeps), standing TALOS under the TSID torque controller."""

import tomllib

import numpy as np
import pytest

import corps
from conftest import REPO

SCENARIO = str(REPO / "scenarios/control/tsid_torque_stand.toml")


class PenaltyFloor(corps.Plant):
    """Rigid robot on a flat floor at z = 0: each sole's four corners push back with a
    spring-damper normal force and viscous friction clipped to the Coulomb cone; semi-implicit
    Euler on the configuration manifold, `substeps` per control period."""

    def __init__(self, model, feet, stiffness=2e6, damping=4e3, friction=1.0, viscous=2e4,
                 substeps=10):
        self.model, self.data = model, model.create_data()
        self.feet = feet  # [(frame name, 4 × 3 corners in the frame)]
        self.k, self.d, self.mu, self.c, self.n = stiffness, damping, friction, viscous, substeps
        self.calls = {"reset": 0, "step": 0, "state": 0}

    def reset(self, q, v, t, dt):
        self.q, self.v, self.t, self.dt = q.copy(), v.copy(), t, dt
        self.tau, self.contacts = np.zeros(self.model.nv), np.zeros((0, 7))
        self.calls["reset"] += 1

    def step(self, command):
        assert command.kind == "torque"
        self.tau = np.concatenate([np.zeros(6), command.torque])
        h = self.dt / self.n
        for _ in range(self.n):
            generalized, rows = self.tau.copy(), []
            corps.compute_joint_jacobians(self.model, self.data, self.q)
            for frame, corners in self.feet:
                placement = corps.frame_placement(self.model, self.data, frame)
                jac = corps.get_frame_jacobian(self.model, self.data, frame,
                                               corps.LOCAL_WORLD_ALIGNED)
                twist = jac @ self.v
                joint = self.model.frame_parent_joint(frame)
                for corner in corners:
                    p = placement.act(corner)
                    if p[2] >= 0.0:
                        continue
                    r = p - placement.translation
                    vel = twist[:3] + np.cross(twist[3:], r)
                    fz = max(0.0, -self.k * p[2] - self.d * vel[2])
                    ft = -self.c * vel[:2]
                    norm = np.linalg.norm(ft)
                    if norm > self.mu * fz:
                        ft *= self.mu * fz / norm
                    f = np.array([ft[0], ft[1], fz])
                    # Point Jacobian: J_p = J_lin - [r]x J_ang (LOCAL_WORLD_ALIGNED at the frame).
                    jp = jac[:3] - np.cross(r, jac[3:].T).T
                    generalized += jp.T @ f
                    rows.append([joint, *p, *f])
            a = corps.aba(self.model, self.data, self.q, self.v, generalized)
            self.v = self.v + h * a
            self.q = corps.integrate(self.model, self.q, h * self.v)
            self.t += h
        self.contacts = np.array(rows) if rows else np.zeros((0, 7))
        self.calls["step"] += 1

    def state(self):
        self.calls["state"] += 1
        return {"t": self.t, "q": self.q, "v": self.v, "tau": self.tau[6:],
                "contacts": self.contacts}


def talos_plant():
    description = tomllib.loads((REPO / "robots/talos_data/talos.toml").read_text())
    model = corps.Model.from_robot("talos")
    feet = []
    for foot in description["feet"]:
        s = foot["sole"]
        corners = [np.array([x, y, 0.0]) for x in (s["front"], -s["back"])
                   for y in (s["left"], -s["right"])]
        feet.append((foot["frame"], corners))
    return PenaltyFloor(model, feet)


def test_python_plant_stands_under_tsid_torque():
    plant = talos_plant()
    result = corps.run(SCENARIO, duration=1.0, plant=plant)
    assert plant.calls["reset"] == 1 and plant.calls["step"] == 1000
    assert result.verdict == "completed", result.report
    mass = plant.model.total_mass()
    # The feet carry the robot (read through the F/T sensors from the plant's contacts).
    support = result["left_foot_fz"][-100:] + result["right_foot_fz"][-100:]
    assert abs(np.mean(support) - 9.81 * mass) < 0.05 * 9.81 * mass, np.mean(support)
    # The base stays put (m): the controller holds the robot on a floor it does not model.
    drift = np.hypot(result["base_x"] - result["base_x"][0], result["base_y"] - result["base_y"][0])
    assert drift.max() < 0.01, drift.max()
    assert np.ptp(result["com_z"]) < 0.01


class Broken(corps.Plant):
    def __init__(self, fail):
        self.fail = fail

    def reset(self, q, v, t, dt):
        self.q, self.v, self.t, self.t0 = q, v, t, t

    def step(self, command):
        if self.fail == "raise":
            raise RuntimeError("the bridge lost the robot")
        self.t += 0.001

    def state(self):
        if self.fail == "size":
            return {"t": self.t, "q": self.q[:-1], "v": self.v}
        if self.fail == "nan" and self.t > self.t0 + 0.01:
            return {"t": self.t, "q": self.q * np.nan, "v": self.v}
        return {"t": self.t, "q": self.q, "v": self.v}


def test_a_plants_exception_comes_back():
    with pytest.raises(RuntimeError, match="lost the robot"):
        corps.run(SCENARIO, duration=0.1, plant=Broken("raise"))


def test_a_broken_protocol_is_a_plant_error():
    with pytest.raises(corps.PlantError, match="'q' has size 38, expected 39"):
        corps.run(SCENARIO, duration=0.1, plant=Broken("size"))
    with pytest.raises(corps.PlantError, match="no method 'reset'"):
        corps.run(SCENARIO, duration=0.1, plant=object())


def test_a_state_that_blows_up_is_diverged():
    result = corps.run(SCENARIO, duration=0.1, plant=Broken("nan"))
    assert result.verdict == "diverged"
    assert result.metrics["verdict"]["t"] == pytest.approx(0.01, abs=2e-3)
