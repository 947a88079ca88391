"""MuJoCo as a plant: the scene is corps' own model (checked body by body against MuJoCo's
kinematics and mass matrix), states convert both ways, and corps' TSID torque controller
stands and rides out a push on it."""

import subprocess
import sys

import numpy as np
import pytest

import corps
from conftest import REPO, random_state

import mujoco  # noqa: E402 (installed by python/setup_venv.sh)

from corps.mujoco_plant import MujocoPlant  # noqa: E402

STAND = str(REPO / "scenarios/control/tsid_torque_stand.toml")
PUSH = str(REPO / "scenarios/control/tsid_torque_push_front.toml")


@pytest.fixture(scope="module", params=["talos", "icub"])
def plant(request):
    return MujocoPlant(request.param)


def test_the_scene_is_corps_model(plant):
    m, model = plant.m, plant.model
    assert abs(sum(m.body_mass) - model.total_mass()) < 1e-9
    assert m.nv == model.nv and m.njnt == model.njoints
    data, rng = model.create_data(), np.random.default_rng(3)
    for _ in range(5):
        q, v, _, _ = random_state(model, rng)
        plant.reset(q, v, 0.0, 1e-3)
        q2, v2 = plant._from_mujoco()
        assert np.allclose(q2, q, atol=1e-14) and np.allclose(v2, v, atol=1e-14)
        corps.forward_kinematics(model, data, q)
        for k, name in enumerate(plant.body_names):
            body = m.body(name).id
            oMi = data.oMi[k]
            assert np.allclose(plant.d.xpos[body], oMi.translation, atol=1e-12), name
            assert np.allclose(plant.d.xmat[body].reshape(3, 3), oMi.rotation, atol=1e-12), name
        # The joints' block of M (the free joint's velocity is expressed differently).
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, plant.d, full)
        dofs = [j[4] for j in plant.joints if j[2] != "free"]
        ivs = [j[1] for j in plant.joints if j[2] != "free"]
        ours = corps.crba(model, data, q)[np.ix_(ivs, ivs)]
        assert np.max(np.abs(full[np.ix_(dofs, dofs)] - ours)) < 1e-9 * np.max(np.abs(ours))


def test_tsid_stands_on_mujoco():
    p = MujocoPlant("talos")
    r = corps.run(STAND, duration=2.0, plant=p)
    assert r.verdict == "completed", r.report
    weight = 9.81 * p.model.total_mass()
    support = r["left_foot_fz"][-200:] + r["right_foot_fz"][-200:]
    assert abs(support.mean() - weight) < 0.01 * weight
    assert r.metrics["base_drift"] < 0.005


def test_a_push_reaches_mujoco():
    r = corps.run(PUSH, duration=2.5, plant=MujocoPlant("talos"))
    t, x = r["t"], r["base_x"]
    excursion = np.max(np.abs(x[t > 1.0] - x[(t > 0.5) & (t < 1.0)].mean()))
    assert r.verdict == "completed"
    assert 0.01 < excursion < 0.05, excursion  # 100 N × 0.1 s on 90 kg: ~0.11 m/s


@pytest.mark.parametrize("scenario", ["tsid_position_stand"])
def test_position_controllers_stand_on_mujoco(scenario):
    """Position commands through corps' servo gains (MuJoCo actuators, damping implicit).
    The IK position controller does not stand on MuJoCo (RESULTS.md: diverged at 0.23 s)."""
    r = corps.run(str(REPO / f"scenarios/control/{scenario}.toml"), duration=2.0,
                  plant=MujocoPlant("talos"))
    assert r.verdict == "completed", r.report
    assert r.metrics["base_drift"] < 0.01
    com = [r.metrics["com_error"][k]["peak"] for k in range(3)]
    assert max(com) < 0.01, com


def test_the_command_line(tmp_path):
    out = tmp_path / "log.csv"
    done = subprocess.run([sys.executable, "-m", "corps", "run", STAND, "--plant", "mujoco",
                           "--duration", "0.3", "--csv", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "verdict: completed" in done.stdout
    assert out.read_text().splitlines()[0].startswith("t,com_x")


class NanTorques(MujocoPlant):
    """Sends MuJoCo a NaN torque after 50 ms: its state blows up."""

    def step(self, command):
        if self.d.time - self.t0 > 0.05:
            class Bad:
                kind, torque = "torque", np.full(len(command.torque), np.nan)
            command = Bad()
        super().step(command)

    def reset(self, q, v, t, dt):
        super().reset(q, v, t, dt)
        self.t0 = t


def test_a_blown_up_mujoco_state_ends_the_run_as_diverged():
    r = corps.run(STAND, duration=0.3, plant=NanTorques("talos"))
    assert r.verdict == "diverged", r.report
    assert r.metrics["verdict"]["t"] < 0.1
