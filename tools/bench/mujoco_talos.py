"""MuJoCo's step time on the TALOS standing scene of corps-sim's `simulation` benchmark.

What is measured: the wall time of `mujoco.mj_step` (one 1 ms step, C loop through
`nstep`, no Python per step) of TALOS (`talos_reduced_box.urdf`, box feet) standing on a
flat floor under a joint PD hold of the SRDF's half-sitting, for the `implicitfast` and
`RK4` integrators. Each integrator gets a fresh scene that first settles 500 steps (as
`crates/corps-sim/benches/simulation.rs` does), then `--steps` steps are timed in each of
`--rounds` rounds; the median and min µs per step over the rounds are printed, with a
standing check (contacts, foot normal force against the weight, base height drift).

The scene, rebuilt from the URDF at run time to match corps':
- every <visual> and every mesh collision dropped (corps simulates no meshes), the root
  link given a free joint, joint damping, friction loss and armature zeroed, joint position
  limits off (corps applies none), robot geoms colliding with the floor only (corps has no
  self-collision), floor plane at z = 0 with friction 0.8, gravity -9.81 z, dt = 1 ms;
- half-sitting from the SRDF (other joints 0), the base raised so that the lowest point of
  the box/cylinder/sphere collisions is at z = 0 (corps' `place_on_ground`);
- corps' `ServoGains::high_gain(model, q, 0.02, 1.0)`: kp = effort / 0.02 rad,
  kd = 2 * 1.0 * sqrt(kp / (M^-1)_ii) at the start configuration, as general actuators with
  force = kp (q_ref - q) - kd qdot, clamped at the URDF effort (corps' `Actuators::torques`
  clamps there too).
MuJoCo's own contact model (soft constraints, default solref/solimp, pyramidal cone,
Newton solver) is kept: that is the thing being compared.

Run: ~/.cache/corps-anchors/mujoco-venv/bin/python tools/bench/mujoco_talos.py
(the venv holds `pip install mujoco numpy`; options --rounds, --steps).
"""

import argparse
import statistics
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "robots/talos_data/robots/talos_reduced_box.urdf"
SRDF = ROOT / "robots/talos_data/srdf/talos.srdf"
DT = 1e-3
FRICTION = 0.8
SATURATION_ANGLE = 0.02  # rad: kp = effort / this
DAMPING_RATIO = 1.0
SETTLE_STEPS = 500
PRIMITIVES = (mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_CYLINDER, mujoco.mjtGeom.mjGEOM_SPHERE)


def urdf_without_visuals_and_meshes():
    """The URDF text with no <visual> and no mesh <collision>, and each joint's effort limit."""
    robot = ET.parse(URDF).getroot()
    for link in robot.findall("link"):
        for v in link.findall("visual"):
            link.remove(v)
        for c in link.findall("collision"):
            if c.find("geometry/mesh") is not None:
                link.remove(c)
    efforts = {
        j.get("name"): float(j.find("limit").get("effort"))
        for j in robot.findall("joint")
        if j.get("type") in ("revolute", "continuous", "prismatic")
    }
    return ET.tostring(robot, encoding="unicode"), efforts


def half_sitting():
    """Joint name -> value of the SRDF's half_sitting (the root joint left out)."""
    srdf = ET.parse(SRDF).getroot()
    state = next(g for g in srdf.iter("group_state") if g.get("name") == "half_sitting")
    return {
        j.get("name"): float(j.get("value"))
        for j in state.findall("joint")
        if len(j.get("value").split()) == 1
    }


def zeroed(x):
    """A zero of the same shape (joint damping is a scalar before MuJoCo 4, a vector after)."""
    return np.zeros_like(x) if np.ndim(x) else 0.0


def build_spec():
    text, efforts = urdf_without_visuals_and_meshes()
    spec = mujoco.MjSpec.from_string(text)
    # One gripper link's full inertia has principal moments off the triangle inequality
    # (beyond MuJoCo's tolerance); MuJoCo refuses it unless it may nudge them.
    spec.compiler.balanceinertia = True
    spec.option.timestep = DT
    spec.option.gravity = [0.0, 0.0, -9.81]
    base = spec.worldbody.first_body()
    base.add_freejoint()
    for j in spec.joints:
        if j.type == mujoco.mjtJoint.mjJNT_FREE:
            continue
        j.damping = zeroed(j.damping)
        j.frictionloss = 0.0
        j.armature = 0.0
        j.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        j.actfrclimited = mujoco.mjtLimited.mjLIMITED_FALSE  # the actuator clamps instead
    for g in spec.geoms:  # robot geoms touch the floor only
        g.contype, g.conaffinity = 1, 0
    floor = spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], pos=[0, 0, 0]
    )
    floor.contype, floor.conaffinity = 0, 1
    floor.friction = [FRICTION, 0.005, 0.0001]
    floor.priority = 1  # the floor's friction is the pair's (not the max of both geoms')
    return spec, efforts


def lowest_point(m, d):
    """Lowest world z over the box, cylinder and sphere geoms of the robot."""
    z = np.inf
    for g in range(m.ngeom):
        t = int(m.geom_type[g])  # a plain int: numpy ints are never `in` a tuple of enums
        if m.geom_bodyid[g] == 0 or t not in PRIMITIVES:
            continue
        c, r, s = d.geom_xpos[g], d.geom_xmat[g].reshape(3, 3), m.geom_size[g]
        if t == mujoco.mjtGeom.mjGEOM_BOX:
            low = c[2] - np.abs(r[2]) @ s
        elif t == mujoco.mjtGeom.mjGEOM_CYLINDER:
            az = abs(r[2, 2])
            low = c[2] - az * s[1] - s[0] * np.sqrt(max(0.0, 1.0 - az * az))
        else:
            low = c[2] - s[0]
        z = min(z, low)
    return z


def standing_talos(integrator):
    """A settled scene: (model, data, base height at the end of the settle)."""
    spec, efforts = build_spec()
    m = spec.compile()
    d = mujoco.MjData(m)
    ref = half_sitting()
    hinges = [j for j in range(m.njnt) if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE]
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in hinges]
    d.qpos[:] = 0.0
    d.qpos[3] = 1.0  # identity base orientation
    for j, name in zip(hinges, names):
        d.qpos[m.jnt_qposadr[j]] = ref.get(name, 0.0)
    mujoco.mj_kinematics(m, d)
    d.qpos[2] -= lowest_point(m, d)

    # corps' ServoGains::high_gain at the start configuration.
    mujoco.mj_forward(m, d)
    minv = np.zeros((m.nv, m.nv))  # rows of M^-1 from M's factorization (M^-1 is symmetric)
    mujoco.mj_solveM(m, d, minv, np.eye(m.nv))
    q_ref = np.array([d.qpos[m.jnt_qposadr[j]] for j in hinges])
    for j, name, target in zip(hinges, names, q_ref):
        dof = m.jnt_dofadr[j]
        kp = efforts[name] / SATURATION_ANGLE
        kd = 2.0 * DAMPING_RATIO * np.sqrt(kp / minv[dof, dof])
        a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.gaintype, a.biastype = mujoco.mjtGain.mjGAIN_FIXED, mujoco.mjtBias.mjBIAS_AFFINE
        a.gainprm[0] = kp
        a.biasprm[:3] = [0.0, -kp, -kd]
        a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        a.forcerange = [-efforts[name], efforts[name]]
    spec.option.integrator = integrator

    qpos = d.qpos.copy()
    m = spec.compile()
    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    d.ctrl[:] = q_ref  # actuators were added in joint order
    mujoco.mj_step(m, d, nstep=SETTLE_STEPS)
    return m, d


def foot_report(m, d):
    """Contact count, total normal force, and which foot boxes carry load."""
    foot_geoms = {
        g for g in range(m.ngeom)
        if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX and "leg_" in m.body(m.geom_bodyid[g]).name
    }
    wrench = np.zeros(6)
    total, loaded = 0.0, set()
    for i in range(d.ncon):
        c = d.contact[i]
        mujoco.mj_contactForce(m, d, i, wrench)
        total += wrench[0]
        for g in (c.geom1, c.geom2):
            if g in foot_geoms and wrench[0] > 0.0:
                loaded.add(g)
    return d.ncon, total, len(loaded), len(foot_geoms)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--steps", type=int, default=2000)
    args = p.parse_args()
    print(f"mujoco {mujoco.__version__}, {args.rounds} rounds x {args.steps} steps of {DT * 1e3:g} ms")
    ok_all = True
    for label, integrator in [
        ("implicitfast_1ms", mujoco.mjtIntegrator.mjINT_IMPLICITFAST),
        ("rk4_1ms", mujoco.mjtIntegrator.mjINT_RK4),
    ]:
        m, d = standing_talos(integrator)
        weight = mujoco.mj_getTotalmass(m) * 9.81
        z0 = d.qpos[2]
        per_step, drift = [], 0.0
        for _ in range(args.rounds):
            t = time.perf_counter()
            mujoco.mj_step(m, d, nstep=args.steps)
            per_step.append((time.perf_counter() - t) / args.steps * 1e6)
            drift = max(drift, abs(d.qpos[2] - z0))
        ncon, normal, loaded, feet = foot_report(m, d)
        ok = drift < 1e-3 and loaded == feet == 2 and np.isfinite(d.qpos).all()
        ok_all &= ok
        print(
            f"{label:17s} median {statistics.median(per_step):7.2f} µs/step, "
            f"min {min(per_step):7.2f} µs/step  (real-time factor {1e3 / statistics.median(per_step):.0f})"
        )
        print(
            f"  contacts {ncon}, feet loaded {loaded}/{feet}, normal force {normal:.1f} N "
            f"vs weight {weight:.1f} N ({normal / weight:.3f}); base z {d.qpos[2]:.5f} m, "
            f"drift {drift * 1e3:.4f} mm -> {'stands' if ok else 'DOES NOT STAND'}"
        )
    return 0 if ok_all else 1


if __name__ == "__main__":
    raise SystemExit(main())
