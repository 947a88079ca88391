"""corps.run against the `corps` command on the same scenario: the same rows, the same
verdict, the same one-line errors."""

import csv
import json
import subprocess

import numpy as np
import pytest

import corps
from conftest import REPO

# (scenario, options): a TALOS torque-controlled sinusoid at 1 kHz and iCub stepping under the
# soft-tasks controller at 100 Hz (the robot given as an override, as `--robot` does).
CASES = [
    ("scenarios/control/tsid_torque_com_sinusoid.toml", {"duration": 1.5}),
    ("scenarios/icub/fsm2_stepping.toml", {"duration": 4.0, "robot": "icub"}),
]

# Wall-clock columns differ from run to run.
TIMING = {"tick_us"}


def cli_run(corps_bin, scenario, out, duration=None, robot=None):
    cmd = [corps_bin, "run", str(REPO / scenario), "-o", str(out), "--serial"]
    if duration is not None:
        cmd += [f"--duration={duration}"]
    if robot is not None:
        cmd += ["--robot", robot]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)


def read_log(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


@pytest.mark.parametrize("scenario,options", CASES)
def test_run_matches_the_command(corps_bin, tmp_path, scenario, options):
    done = cli_run(corps_bin, scenario, tmp_path, **options)
    assert done.returncode == 0, done.stderr
    header, logged = read_log(tmp_path / "log.csv")
    result = corps.run(str(REPO / scenario), **options)
    assert result.columns == header
    assert result.verdict == result.expected == "completed"
    every = round((logged[1, 0] - logged[0, 0]) / (result["t"][1] - result["t"][0]))
    ours = result.data[::every]
    assert ours.shape == logged.shape
    keep = [k for k, c in enumerate(header) if c not in TIMING]
    # The same code on the same input: the same numbers, to the last bit.
    assert np.array_equal(ours[:, keep], logged[:, keep])
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    for key in ("verdict", "com_error", "zmp_error", "feet", "work", "base_drift"):
        assert result.metrics[key] == metrics[key], key


def test_result_access():
    result = corps.run(str(REPO / CASES[0][0]), duration=0.2)
    assert len(result) == result.data.shape[0] == 200
    assert np.allclose(np.diff(result.time), 1e-3)
    assert np.shares_memory(result["com_y"], result.data)
    with pytest.raises(KeyError, match="no column 'nope'"):
        result["nope"]
    frame = result.dataframe()
    assert list(frame.columns) == result.columns
    assert np.array_equal(frame["com_z"].to_numpy(), result["com_z"])
    assert "completed" in result.report


@pytest.mark.parametrize(
    "scenario,options",
    [
        ("scenarios/nope.toml", {}),
        ("scenarios/control/tsid_torque_com_sinusoid.toml", {"duration": -1.0}),
        ("scenarios/control/tsid_torque_com_sinusoid.toml", {"robot": "atlas"}),
        ("scenarios/stand_flat.toml", {}),
    ],
)
def test_errors_are_the_commands(corps_bin, tmp_path, scenario, options):
    done = cli_run(corps_bin, scenario, tmp_path, **options)
    assert done.returncode != 0
    line = done.stderr.strip().splitlines()[-1]
    assert line.startswith("corps: error: ")
    with pytest.raises(corps.ScenarioError) as err:
        corps.run(str(REPO / scenario), **options)
    assert str(err.value) == line[len("corps: error: "):]


def test_bad_options():
    with pytest.raises(corps.ScenarioError, match="estimator: 'kalman'"):
        corps.run(str(REPO / CASES[0][0]), estimator="kalman")


def test_a_run_too_long_to_hold_is_refused_before_it_starts():
    with pytest.raises(corps.ScenarioError, match="in memory, over the log cap"):
        corps.run(str(REPO / "scenarios/control/tsid_torque_stand.toml"), duration=1e6)
