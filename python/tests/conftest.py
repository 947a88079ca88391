"""Shared fixtures: the repository's robots, random states, and the `corps` command."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# name -> (URDF, SRDF) of the robots checked against Pinocchio, as their files are in the repo.
ROBOTS = {
    "talos": ("robots/talos_data/robots/talos_reduced.urdf", "robots/talos_data/srdf/talos.srdf"),
    "icub": ("robots/icub_description/robots/icub_reduced.urdf", "robots/icub_description/srdf/icub.srdf"),
}


def random_state(model, rng):
    """q with the base uniform in ±1 m and a uniform unit quaternion, joints uniform within
    their limits; v, a, tau standard normal. Drawn here, independently of both libraries."""
    q = np.zeros(model.nq)
    q[:3] = rng.uniform(-1.0, 1.0, 3)
    quat = rng.normal(size=4)
    q[3:7] = quat / np.linalg.norm(quat)
    lo, hi = model.lower_position_limit[7:], model.upper_position_limit[7:]
    q[7:] = rng.uniform(lo, hi)
    return q, rng.normal(size=model.nv), rng.normal(size=model.nv), rng.normal(size=model.nv)


def corps_binary():
    """The `corps` command: $CORPS_BIN, else built with cargo (release)."""
    path = os.environ.get("CORPS_BIN")
    if path:
        return path
    subprocess.run(["cargo", "build", "--release", "-p", "corps"], cwd=REPO, check=True)
    return str(REPO / "target" / "release" / "corps")


@pytest.fixture(scope="session")
def corps_bin():
    return corps_binary()
