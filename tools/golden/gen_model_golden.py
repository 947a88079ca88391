#!/usr/bin/env python3
"""Golden reference data for crates/corps-model, computed with Pinocchio.

Usage (from anywhere; paths are resolved against the repository root):

    bash ../shared/tools/anchors/setup.sh        # once: venv with pin==4.1.0 at ~/.cache/corps-anchors
    ~/.cache/corps-anchors/venv/bin/python tools/golden/gen_model_golden.py

This regenerates every case, one JSON file per case in crates/corps-model/tests/golden/<case>.json
(see the README.md there for the layout).  Optional arguments restrict the run to some cases:

    ~/.cache/corps-anchors/venv/bin/python tools/golden/gen_model_golden.py talos mixed_joints

The output is deterministic: each case draws its states from its own numpy Generator with a fixed
seed (SEED + case index), and Pinocchio's own random generator is never used.

Conventions of the JSON files:
  * matrices are arrays of rows; rotations are 3x3 arrays of rows;
  * spatial vectors (motions, forces, momenta) are [linear(3); angular(3)], Pinocchio's order;
  * q stores the free-flyer as [x, y, z, qx, qy, qz, qw] and a continuous joint as (cos t, sin t);
  * unbounded limits are Pinocchio's +-numeric_limits<double>::max() (+-1.7976931348623157e308),
    written as plain finite numbers, so strict JSON parsers accept every file;
  * "M" and "Minv" have both triangles filled (Pinocchio only fills the upper one);
  * a frame's "Lambda_lwa" is null when J_lwa M^-1 J_lwa^T is singular (fewer than 6 dofs in the
    chain, e.g. near the root of a fixed-base robot).
"""

import json
import math
import os
import sys

import numpy as np
import pinocchio as pin

SEED = 20240611
N_RANDOM_STATES = 12

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
OUT_DIR = os.path.join(REPO, "crates", "corps-model", "tests", "golden")

TALOS_URDF = "robots/talos_data/robots/talos_reduced.urdf"
ICUB_URDF = "robots/icub_description/robots/icub_reduced.urdf"
SH_URDF = "robots/simple_humanoid_description/urdf/simple_humanoid.urdf"
MIXED_URDF = "crates/corps-model/tests/data/mixed_joints.urdf"

# name -> (urdf, root, srdf or None, frames checked in detail, number of random states)
CASES = {
    "talos": (
        TALOS_URDF, "free_flyer", "robots/talos_data/srdf/talos.srdf",
        ["leg_left_sole_fix_joint", "leg_right_sole_fix_joint", "left_sole_link", "arm_left_7_joint",
         "gripper_left_base_link", "torso_2_link", "base_link"],
        N_RANDOM_STATES),
    "icub": (
        ICUB_URDF, "free_flyer", "robots/icub_description/srdf/icub.srdf",
        ["l_sole", "r_sole_fixed_joint", "l_ankle_roll", "r_wrist_yaw", "l_hand_dh_frame", "chest",
         "neck_yaw"],
        N_RANDOM_STATES),
    "simple_humanoid": (
        SH_URDF, "free_flyer", "robots/simple_humanoid_description/srdf/simple_humanoid.srdf",
        ["l_ankle", "RLEG_ANKLE_R", "LARM_WRIST_R", "r_wrist", "waist", "BODY", "torso"],
        N_RANDOM_STATES),
    "simple_humanoid_fixed": (
        SH_URDF, "fixed", "robots/simple_humanoid_description/srdf/simple_humanoid.srdf",
        ["l_ankle", "RLEG_ANKLE_R", "LARM_WRIST_R", "r_wrist", "waist", "BODY", "torso"],
        N_RANDOM_STATES),
    "mixed_joints": (
        MIXED_URDF, "free_flyer", None,
        ["tool_frame", "tool_fixed", "mid_fixed", "arm_mid_link", "wrist_cont", "gamma_joint",
         "hollow_link", "slider_link"],
        2 * N_RANDOM_STATES),
}

RF = pin.ReferenceFrame


def L(x):
    """numpy / pinocchio value -> nested lists of Python floats."""
    return np.asarray(x, dtype=float).tolist()


def motion(m):
    return L(np.concatenate([m.linear, m.angular]))


def se3(M):
    return {"translation": L(M.translation), "rotation": L(M.rotation)}


def sym_upper(A):
    A = np.array(A)
    return np.triu(A) + np.triu(A, 1).T


def load(case):
    urdf, root, _, _, _ = CASES[case]
    path = os.path.join(REPO, urdf)
    if root == "free_flyer":
        return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    return pin.buildModelFromUrdf(path)


def random_q(model, rng):
    q = np.zeros(model.nq)
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    for j in model.joints[1:]:
        iq, nq, nv = j.idx_q, j.nq, j.nv
        name = j.shortname()
        if name == "JointModelFreeFlyer":
            q[iq:iq + 3] = rng.uniform(-1.0, 1.0, 3)
            quat = rng.standard_normal(4)  # uniform on S^3 once normalized
            q[iq + 3:iq + 7] = quat / np.linalg.norm(quat)  # (x, y, z, w)
        elif nq == 2 and nv == 1:  # continuous (RevoluteUnbounded*): (cos t, sin t)
            t = rng.uniform(-math.pi, math.pi)
            q[iq:iq + 2] = (math.cos(t), math.sin(t))
        elif nq == 1 and nv == 1:
            a, b = lo[iq], hi[iq]
            if not (abs(a) < 1e300 and abs(b) < 1e300):
                a, b = -math.pi, math.pi
            q[iq] = rng.uniform(a, b)
        else:
            raise RuntimeError(f"unhandled joint type {name}")
    assert pin.isNormalized(model, q, 1e-12)
    return q


def frame_block(model, data, fid, Minv):
    J_local = pin.getFrameJacobian(model, data, fid, RF.LOCAL)
    J_world = pin.getFrameJacobian(model, data, fid, RF.WORLD)
    J_lwa = pin.getFrameJacobian(model, data, fid, RF.LOCAL_WORLD_ALIGNED)
    oMf = data.oMf[fid]
    Lam_inv = J_lwa @ Minv @ J_lwa.T
    Lam = None
    if np.linalg.cond(Lam_inv) < 1e10:
        Lam = L(np.linalg.inv(Lam_inv))
    return {
        "translation": L(oMf.translation),
        "rotation": L(oMf.rotation),
        "J_local": L(J_local),
        "J_world": L(J_world),
        "J_lwa": L(J_lwa),
        "classical_acc_lwa": motion(pin.getFrameClassicalAcceleration(model, data, fid, RF.LOCAL_WORLD_ALIGNED)),
        "spatial_acc_local": motion(pin.getFrameAcceleration(model, data, fid, RF.LOCAL)),
        "velocity_local": motion(pin.getFrameVelocity(model, data, fid, RF.LOCAL)),
        # operational-space inertia, computed in numpy: inv(J_lwa Minv J_lwa^T)
        "Lambda_lwa": Lam,
    }


def state_block(model, data, label, q, v, a, tau, frame_ids):
    M = sym_upper(pin.crba(model, data, q))
    Minv = sym_upper(pin.computeMinverse(model, data, q))
    nle = pin.nonLinearEffects(model, data, q, v).copy()
    g = pin.computeGeneralizedGravity(model, data, q).copy()
    rnea = pin.rnea(model, data, q, v, a).copy()
    aba = pin.aba(model, data, q, v, tau).copy()

    pin.centerOfMass(model, data, q, v, a)
    com, vcom, acom = data.com[0].copy(), data.vcom[0].copy(), data.acom[0].copy()
    Jcom = pin.jacobianCenterOfMass(model, data, q).copy()

    Ag = pin.computeCentroidalMap(model, data, q).copy()
    hg_f = pin.computeCentroidalMomentum(model, data, q, v)
    hg = np.concatenate([hg_f.linear, hg_f.angular])
    pin.computeCentroidalMapTimeVariation(model, data, q, v)
    dAg_v = data.dAg @ v
    pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a)
    dhg = np.concatenate([data.dhg.linear, data.dhg.angular])

    C = pin.computeCoriolisMatrix(model, data, q, v).copy()
    kinetic = pin.computeKineticEnergy(model, data, q, v)
    potential = pin.computePotentialEnergy(model, data, q)

    # Self-consistency of what we are about to publish.
    scale = 1.0 + np.abs(M).max()
    assert np.allclose(rnea, M @ a + nle, atol=1e-9 * scale), label
    assert np.allclose(aba, np.linalg.solve(M, tau - nle), atol=1e-8 * (1 + np.abs(aba).max())), label
    assert np.allclose(Minv @ M, np.eye(model.nv), atol=1e-8), label
    assert np.allclose(nle, C @ v + g, atol=1e-9 * scale), label
    assert np.allclose(hg, Ag @ v, atol=1e-10 * scale), label
    assert np.allclose(dhg, Ag @ a + dAg_v, atol=1e-9 * scale), label
    assert abs(kinetic - 0.5 * v @ M @ v) < 1e-9 * scale * (1 + v @ v), label

    J_world = pin.computeJointJacobians(model, data, q).copy()
    pin.forwardKinematics(model, data, q, v, a)
    pin.updateFramePlacements(model, data)
    joints = [
        {
            "translation": L(data.oMi[i].translation),
            "rotation": L(data.oMi[i].rotation),
            "v_local": motion(data.v[i]),
            "a_local": motion(data.a[i]),
        }
        for i in range(1, model.njoints)
    ]
    frames = {}
    for name, fid in frame_ids.items():
        fb = frame_block(model, data, fid, Minv)
        # cross-check against the self-contained entry point
        J2 = pin.computeFrameJacobian(model, data.copy(), q, fid, RF.LOCAL_WORLD_ALIGNED)
        assert np.allclose(J2, fb["J_lwa"], atol=1e-12), (label, name)
        frames[name] = fb

    return {
        "label": label,
        "q": L(q), "v": L(v), "a": L(a), "tau": L(tau),
        "M": L(M), "Minv": L(Minv),
        "nle": L(nle), "g": L(g), "rnea": L(rnea), "aba": L(aba),
        "com": L(com), "vcom": L(vcom), "acom": L(acom), "Jcom": L(Jcom),
        "Ag": L(Ag), "hg": L(hg), "dAg_v": L(dAg_v), "dhg": L(dhg),
        "C": L(C),
        "kinetic": float(kinetic), "potential": float(potential),
        "joints": joints,
        "J_world": L(J_world),
        "frames": frames,
    }


def joint_axis(jm):
    """Axis of 1-dof joints as Pinocchio stores it (None for other joints)."""
    s = jm.shortname()
    for suffix, ax in (("X", [1.0, 0.0, 0.0]), ("Y", [0.0, 1.0, 0.0]), ("Z", [0.0, 0.0, 1.0])):
        if s in ("JointModelR" + suffix, "JointModelP" + suffix, "JointModelRUB" + suffix):
            return ax
    if s in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned",
             "JointModelRevoluteUnboundedUnaligned"):
        return L(jm.extract().axis)
    return None


def generate(case, index):
    urdf, root, srdf, frame_names, n_random = CASES[case]
    model = load(case)
    data = model.createData()
    rng = np.random.default_rng(SEED + index)

    frame_ids = {}
    for name in frame_names:
        if model.existFrame(name):
            frame_ids[name] = model.getFrameId(name)
        else:
            print(f"[{case}] frame {name!r} not in model, skipped", file=sys.stderr)

    ref_confs = None
    ref_error = None
    if srdf is not None:
        try:
            pin.loadReferenceConfigurations(model, os.path.join(REPO, srdf), False)
            # the boost-python std::map wrapper iterates over entries with key()/data()
            ref_confs = {e.key(): L(e.data()) for e in model.referenceConfigurations}
        except Exception as e:  # reported in the file and on stderr
            ref_error = f"{type(e).__name__}: {e}"
            print(f"[{case}] loadReferenceConfigurations failed: {ref_error}", file=sys.stderr)

    states = []
    # state 0: neutral configuration at rest (pure gravity); then random states.
    q0 = pin.neutral(model)
    z = np.zeros(model.nv)
    states.append(state_block(model, data, "neutral_rest", q0, z, z, z, frame_ids))
    for k in range(n_random):
        q = random_q(model, rng)
        v = rng.standard_normal(model.nv)
        a = rng.standard_normal(model.nv)
        tau = rng.standard_normal(model.nv)
        states.append(state_block(model, data, f"random_{k}", q, v, a, tau, frame_ids))

    out = {
        "generator": "tools/golden/gen_model_golden.py",
        "pinocchio_version": pin.__version__,
        "urdf": urdf,
        "root": root,
        "seed": SEED + index,
        "gravity": motion(model.gravity),
        "nq": model.nq,
        "nv": model.nv,
        "mass": pin.computeTotalMass(model),
        "joint_names": list(model.names)[1:],
        "joint_types": [j.shortname() for j in model.joints][1:],
        "joint_axes": [joint_axis(j) for j in model.joints][1:],
        "joint_idx_q": list(model.idx_qs)[1:],
        "joint_idx_v": list(model.idx_vs)[1:],
        "joint_nq": list(model.nqs)[1:],
        "joint_nv": list(model.nvs)[1:],
        "joint_parents": list(model.parents)[1:],
        "joint_placements": [se3(model.jointPlacements[i]) for i in range(1, model.njoints)],
        "body_masses": [model.inertias[i].mass for i in range(1, model.njoints)],
        "body_levers": [L(model.inertias[i].lever) for i in range(1, model.njoints)],
        # full inertias, index 0 = universe (non-zero for a fixed base: the root link is merged there)
        "body_inertias": [
            {"mass": model.inertias[i].mass, "lever": L(model.inertias[i].lever),
             "rotational_inertia_at_com": L(model.inertias[i].inertia)}
            for i in range(model.njoints)
        ],
        "frames": list(frame_ids.keys()),
        "frame_list": [
            {"name": f.name, "type": str(f.type), "parent_joint": int(f.parentJoint),
             "parent_frame": int(f.parentFrame), "placement": se3(f.placement),
             "inertia_mass": f.inertia.mass}
            for f in model.frames
        ],
        "lower_limits": L(model.lowerPositionLimit),
        "upper_limits": L(model.upperPositionLimit),
        "velocity_limits": L(model.velocityLimit),
        "effort_limits": L(model.effortLimit),
        "reference_configurations": ref_confs,
        "reference_configurations_error": ref_error,
        "states": states,
    }
    os.makedirs(OUT_DIR, exist_ok=True)
    path = os.path.join(OUT_DIR, f"{case}.json")
    with open(path, "w") as fh:
        json.dump(out, fh, allow_nan=False, separators=(",", ":"))
        fh.write("\n")
    print(f"{case}: nq={model.nq} nv={model.nv} states={len(states)} frames={len(frame_ids)} "
          f"-> {os.path.relpath(path, REPO)} ({os.path.getsize(path) / 1e6:.2f} MB)")


def main(argv):
    names = argv[1:] or list(CASES)
    for name in names:
        if name not in CASES:
            raise SystemExit(f"unknown case {name!r}; known: {', '.join(CASES)}")
    for index, name in enumerate(CASES):
        if name in names:
            generate(name, index)


if __name__ == "__main__":
    main(sys.argv)
