"""Bad input raises a Python exception with a one-line message; nothing crashes."""

import numpy as np
import pytest

import corps
from conftest import REPO, ROBOTS


@pytest.fixture(scope="module")
def talos():
    urdf, srdf = (str(REPO / p) for p in ROBOTS["talos"])
    return corps.Model.from_urdf(urdf, srdf=srdf)


def test_sizes(talos):
    data, q = talos.create_data(), corps.neutral(talos)
    z = np.zeros(talos.nv)
    with pytest.raises(corps.ModelError, match="configuration q has size 38, expected 39"):
        corps.rnea(talos, data, q[:-1], z, z)
    with pytest.raises(corps.ModelError, match="size 37, expected 38"):
        corps.aba(talos, data, q, z, z[:-1])
    with pytest.raises(corps.ModelError):
        corps.rnea(talos, data, np.full(talos.nq, np.nan), z, z)


def test_frames(talos):
    data, q = talos.create_data(), corps.neutral(talos)
    with pytest.raises(corps.ModelError, match="unknown frame 'no_such_link'"):
        corps.compute_frame_jacobian(talos, data, q, "no_such_link")
    with pytest.raises(corps.ModelError, match="out of range"):
        corps.compute_frame_jacobian(talos, data, q, 10_000)
    with pytest.raises(TypeError):
        corps.compute_frame_jacobian(talos, data, q, "left_sole_link", "WORLD")


def test_data_of_another_model(talos):
    other = corps.Model.from_robot("simple_humanoid")
    z = np.zeros(talos.nv)
    with pytest.raises(corps.ModelError, match="data was created by another model"):
        corps.rnea(talos, other.create_data(), corps.neutral(talos), z, z)


def test_files():
    with pytest.raises(corps.ModelError, match="cannot read"):
        corps.Model.from_urdf("/no/such/robot.urdf")
    with pytest.raises(corps.ModelError, match="unknown robot 'atlas'|atlas"):
        corps.Model.from_robot("atlas")


def test_builtin_robot_models():
    icub = corps.Model.from_robot("icub")
    assert icub.nv == 6 + 23  # neck and wrists locked by the description (seed 001)
    backpacked = corps.Model.from_robot("icub_backpacked")
    assert backpacked.total_mass() > icub.total_mass()


def test_a_panic_is_an_exception():
    with pytest.raises(corps.CorpsError, match="internal error in corps"):
        corps._corps._panic_for_test()
