"""corps' rigid-body algorithms against Pinocchio (`pin` from PyPI) on random states of TALOS
and iCub, to 1e-10 relative (‖corps − pin‖∞ / max(‖pin‖∞, 1))."""

import numpy as np
import pinocchio as pin
import pytest

import corps
from conftest import REPO, ROBOTS, random_state

TOL = 1e-10
STATES = 8


def rel(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1.0)


def sym(upper):
    """Pinocchio fills the upper triangle of M and M⁻¹; corps both."""
    return np.triu(upper) + np.triu(upper, 1).T


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def pair(request):
    urdf, srdf = (str(REPO / p) for p in ROBOTS[request.param])
    model = corps.Model.from_urdf(urdf, srdf=srdf, floating_base=True)
    pmodel = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    return request.param, model, model.create_data(), pmodel, pmodel.createData()


@pytest.fixture(scope="module")
def states(pair):
    name, model = pair[0], pair[1]
    rng = np.random.default_rng(20261127 + sum(map(ord, name)))
    return [random_state(model, rng) for _ in range(STATES)]


def test_same_layout(pair):
    _, model, _, pmodel, _ = pair
    assert (model.nq, model.nv) == (pmodel.nq, pmodel.nv)
    assert model.joint_names == list(pmodel.names)[1:]
    assert model.idx_qs == [pmodel.joints[i].idx_q for i in range(1, pmodel.njoints)]
    assert model.idx_vs == [pmodel.joints[i].idx_v for i in range(1, pmodel.njoints)]
    assert rel(model.lower_position_limit[7:], pmodel.lowerPositionLimit[7:]) == 0.0
    assert rel(model.effort_limit[6:], pmodel.effortLimit[6:]) == 0.0
    assert abs(model.total_mass() - pin.computeTotalMass(pmodel)) < 1e-12


def test_inverse_and_forward_dynamics(pair, states):
    _, model, data, pmodel, pdata = pair
    for q, v, a, tau in states:
        assert rel(corps.rnea(model, data, q, v, a), pin.rnea(pmodel, pdata, q, v, a)) < TOL
        assert rel(data.tau, pdata.tau) < TOL
        assert rel(corps.nonlinear_effects(model, data, q, v),
                   pin.nonLinearEffects(pmodel, pdata, q, v)) < TOL
        assert rel(corps.compute_generalized_gravity(model, data, q),
                   pin.computeGeneralizedGravity(pmodel, pdata, q)) < TOL
        assert rel(corps.crba(model, data, q), sym(pin.crba(pmodel, pdata, q))) < TOL
        assert rel(corps.compute_minverse(model, data, q),
                   sym(pin.computeMinverse(pmodel, pdata, q))) < TOL
        assert rel(corps.aba(model, data, q, v, tau), pin.aba(pmodel, pdata, q, v, tau)) < TOL


def test_kinematics_and_frames(pair, states):
    _, model, data, pmodel, pdata = pair
    names = [n for n in model.frame_names if pmodel.existFrame(n)]
    assert len(names) >= 0.9 * len(model.frame_names)
    for q, v, a, _ in states:
        corps.forward_kinematics(model, data, q, v, a)
        pin.forwardKinematics(pmodel, pdata, q, v, a)
        pin.updateFramePlacements(pmodel, pdata)
        for i, m in enumerate(data.oMi):
            assert rel(m.homogeneous, pdata.oMi[i + 1].homogeneous) < TOL
        for name in names:
            pid = pmodel.getFrameId(name)
            assert rel(corps.frame_placement(model, data, name).homogeneous,
                       pdata.oMf[pid].homogeneous) < TOL, name
        pin.computeJointJacobians(pmodel, pdata, q)
        assert rel(corps.compute_joint_jacobians(model, data, q), pdata.J) < TOL
        for name in names[:: max(1, len(names) // 12)]:
            pid = pmodel.getFrameId(name)
            for ours, theirs in ((corps.LOCAL, pin.LOCAL), (corps.WORLD, pin.WORLD),
                                 (corps.LOCAL_WORLD_ALIGNED, pin.LOCAL_WORLD_ALIGNED)):
                j = corps.compute_frame_jacobian(model, data, q, name, ours)
                pj = pin.computeFrameJacobian(pmodel, pdata, q, pid, theirs)
                assert rel(j, pj) < TOL, (name, ours)
                assert rel(corps.get_frame_jacobian(model, data, model.get_frame_id(name), ours), pj) < TOL


def test_center_of_mass_and_centroidal(pair, states):
    _, model, data, pmodel, pdata = pair
    for q, v, a, _ in states:
        assert rel(corps.center_of_mass(model, data, q, v, a),
                   pin.centerOfMass(pmodel, pdata, q, v, a)) < TOL
        assert rel(data.vcom, pdata.vcom[0]) < TOL
        assert rel(data.acom, pdata.acom[0]) < TOL
        assert rel(corps.jacobian_center_of_mass(model, data, q),
                   pin.jacobianCenterOfMass(pmodel, pdata, q)) < TOL
        assert rel(corps.centroidal_map(model, data, q),
                   pin.computeCentroidalMap(pmodel, pdata, q)) < TOL
        assert rel(corps.compute_centroidal_momentum(model, data, q, v),
                   pin.computeCentroidalMomentum(pmodel, pdata, q, v).vector) < TOL
        assert rel(corps.compute_kinetic_energy(model, data, q, v),
                   pin.computeKineticEnergy(pmodel, pdata, q, v)) < TOL
        assert rel(corps.compute_potential_energy(model, data, q),
                   pin.computePotentialEnergy(pmodel, pdata, q)) < TOL


def test_configuration_space(pair, states):
    _, model, _, pmodel, _ = pair
    assert rel(corps.neutral(model), pin.neutral(pmodel)) == 0.0
    for (q0, v, _, _), (q1, _, _, _) in zip(states, states[1:]):
        assert rel(corps.integrate(model, q0, 0.1 * v), pin.integrate(pmodel, q0, 0.1 * v)) < TOL
        assert rel(corps.difference(model, q0, q1), pin.difference(pmodel, q0, q1)) < TOL


def test_inputs_convert_and_are_not_aliased(pair, states):
    _, model, data, _, _ = pair
    q, v, a, _ = states[0]
    tau = corps.rnea(model, data, q, v, a)
    again = corps.rnea(model, data, list(q), v.tolist(), a[::1])  # lists, views
    strided = np.repeat(a, 2)[::2]                                   # non-contiguous
    assert np.array_equal(corps.rnea(model, data, q, v, strided), tau)
    corps.rnea(model, data, q, 0 * v, 0 * a)
    assert np.array_equal(again, tau)  # the first result was not overwritten
