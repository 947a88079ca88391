"""MuJoCo as a plant of corps' runs (`corps.run(..., plant=MujocoPlant(robot))`).

The scene is built from corps' own model of the robot (`Model.from_robot`), not from the URDF
again, so that both plants simulate one robot: the same bodies (fixed links merged), masses,
inertias, locked joints and added bodies, and the same collision primitives (meshes left out,
as corps' simulator leaves them). What differs is the physics, on purpose: MuJoCo's soft
contact constraints (default solref/solimp, pyramidal cone, Newton solver) and its
integrator. As in corps' simulator: no joint limits, no joint damping, friction or armature,
robot geoms collide with the floor only, a flat floor at z = 0 with Coulomb friction
`friction`, torques clamped at the URDF effort limits.

State conversion (Pinocchio's convention on corps' side): MuJoCo's free joint keeps
qpos = [p; w, x, y, z] and qvel = [linear velocity in the world frame; angular velocity in the
body frame]; corps' q = [p; x, y, z, w] and v = [linear; angular], both in the body frame.
"""

from typing import List, Tuple

import numpy as np

import corps

try:
    import mujoco
except ImportError as e:  # pragma: no cover - depends on the environment
    raise ImportError("corps.mujoco_plant needs MuJoCo: pip install mujoco") from e


def _quat_wxyz(rotation: np.ndarray) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rotation).reshape(9))
    return q


def build_spec(model: "corps.Model", timestep: float, friction: float, integrator: str,
               solref: Tuple[float, float] = (0.02, 1.0), cone: str = "pyramidal",
               impratio: float = 1.0) -> Tuple["mujoco.MjSpec", List[str]]:
    """The MuJoCo scene of corps model `model`; returns the spec and the body names in
    corps' joint order."""
    spec = mujoco.MjSpec()
    spec.modelname = model.name
    # MuJoCo refuses a body inertia off the triangle inequality beyond its tolerance (one of
    # TALOS's gripper links); it may nudge those, by an amount far below what the runs see.
    spec.compiler.balanceinertia = True
    spec.option.timestep = timestep
    spec.option.gravity = list(model.gravity)
    spec.option.integrator = {
        "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
        "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
        "rk4": mujoco.mjtIntegrator.mjINT_RK4,
        "euler": mujoco.mjtIntegrator.mjINT_EULER,
    }[integrator]
    spec.option.cone = {"pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL,
                        "elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC}[cone]
    spec.option.impratio = impratio
    # A state that blows up must reach corps (and end the run as diverged), not be reset to
    # the model's initial pose by MuJoCo behind corps' back.
    spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_AUTORESET
    bodies, names = [], []
    for b in model.bodies():
        parent = spec.worldbody if b["parent"] is None else bodies[b["parent"]]
        h = b["placement"]
        body = parent.add_body(name=b["name"], pos=h[:3, 3], quat=_quat_wxyz(h[:3, :3]))
        mass = max(b["mass"], 1e-9)
        inertia = b["inertia"] if b["mass"] > 0 else np.eye(3) * 1e-12
        body.mass = mass
        body.ipos = b["com"]
        body.fullinertia = [inertia[0, 0], inertia[1, 1], inertia[2, 2],
                            inertia[0, 1], inertia[0, 2], inertia[1, 2]]
        body.explicitinertial = True
        if b["kind"] == "free":
            body.add_freejoint(name=b["name"])
        else:
            kind = mujoco.mjtJoint.mjJNT_SLIDE if b["kind"] == "prismatic" else mujoco.mjtJoint.mjJNT_HINGE
            body.add_joint(name=b["name"], type=kind, axis=b["axis"],
                           limited=mujoco.mjtLimited.mjLIMITED_FALSE)
        bodies.append(body)
        names.append(b["name"])
    for k, c in enumerate(model.collisions()):
        if c["joint"] is None:
            continue
        h = c["placement"]
        if c["shape"] == "box":
            kind, size = mujoco.mjtGeom.mjGEOM_BOX, list(np.asarray(c["size"]) / 2.0)
        elif c["shape"] == "cylinder":
            kind, size = mujoco.mjtGeom.mjGEOM_CYLINDER, [c["radius"], c["length"] / 2.0, 0.0]
        else:
            kind, size = mujoco.mjtGeom.mjGEOM_SPHERE, [c["radius"], 0.0, 0.0]
        g = bodies[c["joint"]].add_geom(name=f"{c['link']}_{k}", type=kind, size=size,
                                        pos=h[:3, 3], quat=_quat_wxyz(h[:3, :3]))
        g.contype, g.conaffinity = 1, 0
        g.mass = 0.0
        g.density = 0.0
    # One servo a hinge or slide, at zero gain until `servo()` sets corps' gains: MuJoCo's
    # implicitfast integrates its damping implicitly, as corps-sim integrates its servos.
    for b in model.bodies():
        if b["kind"] == "free":
            continue
        a = spec.add_actuator(name=b["name"], target=b["name"], trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.gaintype, a.biastype = mujoco.mjtGain.mjGAIN_FIXED, mujoco.mjtBias.mjBIAS_AFFINE
        a.gainprm[0] = 0.0
        a.biasprm[:3] = [0.0, 0.0, 0.0]
        if b["effort"] is not None and np.isfinite(b["effort"]):
            a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.forcerange = [-b["effort"], b["effort"]]
    floor = spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE,
                                    size=[0, 0, 1], pos=[0, 0, 0])
    floor.contype, floor.conaffinity = 0, 1
    floor.friction = [friction, 0.005, 0.0001]
    floor.solref = list(solref)
    floor.priority = 1
    return spec, names


#: MuJoCo's contact made as stiff as corps-sim's (see RESULTS.md, "corps-sim against
#: MuJoCo"): a 2 ms constraint time constant, elliptic friction cones, impratio 10.
STIFF = {"solref": (0.002, 1.0), "cone": "elliptic", "impratio": 10.0}


class MujocoPlant(corps.Plant):
    """A robot description's robot in MuJoCo. `robot`: a built-in name or a description
    file; `timestep` (s) the physics step (the control period is a whole number of them);
    `integrator`: implicitfast (default), implicit, rk4 or euler; `friction`: floor μ;
    `solref`, `cone`, `impratio`: MuJoCo's contact softness (its defaults unless given;
    `**STIFF` makes it as stiff as corps-sim's)."""

    def __init__(self, robot: str = "talos", timestep: float = 1e-3, friction: float = 0.8,
                 integrator: str = "implicitfast", solref: Tuple[float, float] = (0.02, 1.0),
                 cone: str = "pyramidal", impratio: float = 1.0):
        self.model = corps.Model.from_robot(robot)
        spec, self.body_names = build_spec(self.model, timestep, friction, integrator,
                                           solref, cone, impratio)
        self.m = spec.compile()
        self.d = mujoco.MjData(self.m)
        self.timestep = timestep
        self.joints = []  # (corps idx_q, idx_v, kind, mujoco qposadr, dofadr, effort)
        for b in self.model.bodies():
            j = self.m.joint(b["name"])
            self.joints.append((b["idx_q"], b["idx_v"], b["kind"], int(j.qposadr[0]),
                                int(j.dofadr[0]), b["effort"]))
        # Index arrays over the hinges and slides, so that a state converts in a few
        # vectorized copies.
        hinges = [j for j in self.joints if j[2] != "free"]
        self.hinge_q = np.array([j[0] for j in hinges], dtype=int)
        self.hinge_qa = np.array([j[3] for j in hinges], dtype=int)
        self.continuous = np.array([j[2] == "continuous" for j in hinges], dtype=bool)
        self.dof_v = np.array([j[1] for j in hinges], dtype=int)
        self.dof_mj = np.array([j[4] for j in hinges], dtype=int)
        self.effort = np.array([np.inf if j[5] is None else j[5] for j in hinges])
        self.free = [j for j in self.joints if j[2] == "free"]
        # Actuator of each hinge, in the order of dof_v.
        self.actuator = np.array([self.m.actuator(n).id for n in
                                  (b["name"] for b in self.model.bodies() if b["kind"] != "free")],
                                 dtype=int)
        self.kp = np.zeros(len(hinges))
        self.kd = np.zeros(len(hinges))
        # MuJoCo body id -> corps joint index (the world body maps to None).
        self.joint_of_body = {self.m.body(n).id: k for k, n in enumerate(self.body_names)}
        self.pushes: List[Tuple[int, np.ndarray, float, float, np.ndarray, np.ndarray]] = []
        self.tau = np.zeros(self.model.nv)
        self.contact_force = np.zeros(6)
        self.rotation = np.zeros(9)

    # -- conversions -----------------------------------------------------------------------
    def _to_mujoco(self, q: np.ndarray, v: np.ndarray) -> None:
        d = self.d
        for iq, iv, _, qa, da, _ in self.free:
            d.qpos[qa:qa + 3] = q[iq:iq + 3]
            d.qpos[qa + 3:qa + 7] = [q[iq + 6], q[iq + 3], q[iq + 4], q[iq + 5]]
            mujoco.mju_quat2Mat(self.rotation, d.qpos[qa + 3:qa + 7])
            d.qvel[da:da + 3] = self.rotation.reshape(3, 3) @ v[iv:iv + 3]
            d.qvel[da + 3:da + 6] = v[iv + 3:iv + 6]
        d.qpos[self.hinge_qa] = self._joint_angles(q)
        d.qvel[self.dof_mj] = v[self.dof_v]

    def _joint_angles(self, q: np.ndarray) -> np.ndarray:
        """The hinge and slide positions of configuration q, in dof_v's order (a continuous
        joint's (cos θ, sin θ) as θ)."""
        out = q[self.hinge_q]
        iq = self.hinge_q[self.continuous]
        out[self.continuous] = np.arctan2(q[iq + 1], q[iq])
        return out

    def _from_mujoco(self) -> Tuple[np.ndarray, np.ndarray]:
        d = self.d
        q, v = np.zeros(self.model.nq), np.zeros(self.model.nv)
        for iq, iv, _, qa, da, _ in self.free:
            w, x, y, z = d.qpos[qa + 3:qa + 7]
            q[iq:iq + 3] = d.qpos[qa:qa + 3]
            q[iq + 3:iq + 7] = [x, y, z, w]
            mujoco.mju_quat2Mat(self.rotation, d.qpos[qa + 3:qa + 7])
            v[iv:iv + 3] = self.rotation.reshape(3, 3).T @ d.qvel[da:da + 3]
            v[iv + 3:iv + 6] = d.qvel[da + 3:da + 6]
        angle = d.qpos[self.hinge_qa]
        bounded = ~self.continuous
        q[self.hinge_q[bounded]] = angle[bounded]
        iq = self.hinge_q[self.continuous]
        q[iq], q[iq + 1] = np.cos(angle[self.continuous]), np.sin(angle[self.continuous])
        v[self.dof_v] = d.qvel[self.dof_mj]
        return q, v

    # -- the plant protocol ----------------------------------------------------------------
    def reset(self, q, v, t, dt):
        mujoco.mj_resetData(self.m, self.d)
        self.pushes.clear()
        self.tau[:] = 0.0
        self._to_mujoco(q, v)
        self.d.time = t
        self.substeps = max(1, int(round(dt / self.timestep)))
        if abs(self.substeps * self.timestep - dt) > 1e-9:
            raise corps.PlantError(
                f"the control period {dt} s is not a whole number of MuJoCo steps of {self.timestep} s")
        mujoco.mj_forward(self.m, self.d)

    def push(self, frame, start, duration, force, torque):
        joint, placement = self.model.frame_attachment(frame)
        if joint is None:
            raise corps.PlantError(f"push on '{frame}': the frame is fixed to the world")
        body = self.m.body(self.body_names[joint]).id
        self.pushes.append((body, placement.translation, start, duration,
                            np.asarray(force, float), np.asarray(torque, float)))

    def _apply_pushes(self) -> None:
        d = self.d
        d.xfrc_applied[:] = 0.0
        for body, offset, start, duration, force, torque in self.pushes:
            if not (start <= d.time < start + duration):
                continue
            point = d.xpos[body] + d.xmat[body].reshape(3, 3) @ offset
            # MuJoCo applies xfrc_applied at the body's centre of mass.
            d.xfrc_applied[body, :3] += force
            d.xfrc_applied[body, 3:] += torque + np.cross(point - d.xipos[body], force)

    def servo(self, kp, kd, ki):
        """corps' servo gains (per actuated joint): position and velocity commands act through
        τ = kp (q_ref − q) + kd (v_ref − v), as in corps' simulator."""
        if ki is not None and np.any(np.asarray(ki) != 0.0):
            raise corps.PlantError("the MuJoCo plant has no PID integral term (actuation.pid_gains)")
        self.kp[:] = kp
        self.kd[:] = kd

    def _set_servos(self, kp, kd):
        self.m.actuator_gainprm[self.actuator, 0] = kp
        self.m.actuator_biasprm[self.actuator, 1] = -kp
        self.m.actuator_biasprm[self.actuator, 2] = -kd

    def step(self, command):
        d = self.d
        d.qfrc_applied[:] = 0.0
        if command.kind == "torque":
            tau = command.torque
            first = self.model.nv - len(tau)
            self.tau[self.dof_v] = np.clip(tau[self.dof_v - first], -self.effort, self.effort)
            d.qfrc_applied[self.dof_mj] = self.tau[self.dof_v]
            self._set_servos(0.0, 0.0)
            d.ctrl[:] = 0.0
        else:
            # kp (q_ref − q) − kd v through the actuators (damping implicit), + kd v_ref applied.
            v_ref = command.v_ref
            kp = self.kp if command.kind == "position" else np.zeros_like(self.kp)
            self._set_servos(kp, self.kd)
            if command.kind == "position":
                d.ctrl[self.actuator] = self._joint_angles(command.q_ref)
            else:
                d.ctrl[:] = 0.0
            d.qfrc_applied[self.dof_mj] = self.kd * v_ref
        for _ in range(self.substeps):
            if self.pushes:
                self._apply_pushes()
            mujoco.mj_step(self.m, self.d)
        if command.kind != "torque":
            self.tau[self.dof_v] = d.qfrc_actuator[self.dof_mj] + d.qfrc_applied[self.dof_mj]
        bad = [w for w in (mujoco.mjtWarning.mjWARN_BADQACC, mujoco.mjtWarning.mjWARN_BADQPOS,
                           mujoco.mjtWarning.mjWARN_BADQVEL) if self.d.warning[w].number > 0]
        if bad:
            # Reported as a non-finite state: corps ends the run as diverged.
            self.d.qpos[:] = np.nan

    def contacts(self) -> np.ndarray:
        """Rows [joint, px, py, pz, fx, fy, fz]: the force on the robot at each contact
        (world frame)."""
        m, d = self.m, self.d
        rows = []
        for i in range(d.ncon):
            c = d.contact[i]
            mujoco.mj_contactForce(m, d, i, self.contact_force)
            # The force of geom1 on geom2 in the contact frame (rows of c.frame are its axes).
            f = c.frame.reshape(3, 3).T @ self.contact_force[:3]
            for geom, sign in ((c.geom2, 1.0), (c.geom1, -1.0)):
                joint = self.joint_of_body.get(int(m.geom_bodyid[geom]))
                if joint is not None:
                    rows.append([joint, *c.pos, *(sign * f)])
        return np.array(rows) if rows else np.zeros((0, 7))

    def state(self):
        # Contacts and their forces at this state (mj_step leaves those of the step's start).
        mujoco.mj_forward(self.m, self.d)
        q, v = self._from_mujoco()
        return {"t": self.d.time, "q": q, "v": v, "tau": self.tau, "contacts": self.contacts()}
