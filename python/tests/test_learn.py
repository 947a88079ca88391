"""`corps.learn`: a learning campaign run from Python, its rollouts on this machine or as Ray
tasks in worker processes, ends with the same files as `corps learn` for the same seeds; bad
Ray addresses and a failing cluster stop it with one clear line, never with a corrupt file."""

import os
import pathlib
import subprocess

import re

import pytest

import corps
from corps import learn as corps_learn

from conftest import REPO, corps_binary

CAMPAIGN = str(REPO / "campaigns" / "icub" / "phi_pr.toml")
TEXT = pathlib.Path(CAMPAIGN).read_text()
# Two repeats of two iterations: the start's randomized draws, candidates, and the tests of
# three weight vectors on both test runs.
SHORT = ["--iterations", "2", "--repeats", "2"]


def files(directory):
    """The campaign's results as text; evaluations sorted (repeats run concurrently)."""
    evaluations = (directory / "evaluations.csv").read_text().splitlines()
    header, rows = evaluations[0], sorted(evaluations[1:])
    return {
        "evaluations": [header] + rows,
        "learned": (directory / "learned.csv").read_text(),
        "tests": (directory / "tests.csv").read_text(),
    }


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The short campaign run by the `corps` command on this machine's threads."""
    out = tmp_path_factory.mktemp("learn") / "command"
    subprocess.run([corps_binary(), "learn", CAMPAIGN, *SHORT, "-o", str(out)], check=True,
                   capture_output=True, cwd=REPO)
    return files(out)


def test_python_learn_writes_what_the_command_writes(reference, tmp_path):
    out = tmp_path / "python"
    text = corps_learn.learn(CAMPAIGN, iterations=2, repeats=2, output=str(out))
    assert "threads" in text and "tests (6 steps)" in text, text
    assert files(out) == reference


def test_a_campaign_on_a_local_ray_instance_ends_as_on_this_machine(reference, tmp_path):
    pytest.importorskip("ray", reason="Ray is not installed (pip install ray): the Ray "
                        "campaign is not run")
    out = tmp_path / "ray"
    code = corps_learn.main([CAMPAIGN, *SHORT, "-o", str(out), "--ray", "local",
                             "--ray-cpus", "2"])
    assert code == 0
    assert files(out) == reference


def test_a_ray_worker_returns_what_this_machine_computes():
    pytest.importorskip("ray", reason="Ray is not installed (pip install ray)")
    cluster = corps_learn.RayMap(CAMPAIGN, "local", cpus=2)
    try:
        weights = [1.0, 1.0, 1.0, 0.1, 1e-3, 1e-4]
        jobs = [(None, weights, seed) for seed in (3, 4)] + [(0, weights, 5)]
        remote = cluster(jobs)
        # The CPUs the instance reports, not the argument.
        assert cluster.description.endswith(", 2 CPUs"), cluster.description
    finally:
        cluster.close()
    here = [corps._corps.learning_rollout(CAMPAIGN, TEXT, job) for job in jobs]
    assert [tuple(r) for r in remote] == here
    fitness, g_joint, g_torque, failed, error, steps, verdict = here[2]
    assert verdict.split()[0] in {"completed", "fell", "diverged", "controller_failed"}, verdict
    assert isinstance(steps, int) and isinstance(failed, bool)


@pytest.mark.parametrize("address, cpus, words", [
    ("127.0.0.1:1", None, "cannot reach a Ray head at 127.0.0.1:1"),
    ("nowhere", None, "is not 'auto', 'local' or HOST:PORT"),
    ("auto", 2, "--ray-cpus: only with --ray local"),
])
def test_a_bad_ray_address_stops_before_any_rollout(tmp_path, address, cpus, words):
    pytest.importorskip("ray", reason="Ray is not installed (pip install ray)")
    out = tmp_path / "bad"
    with pytest.raises(corps.ScenarioError, match=re.escape(words)):
        corps_learn.learn(CAMPAIGN, iterations=1, repeats=1, output=str(out), ray=address,
                          ray_cpus=cpus)
    assert not out.exists()


def test_auto_without_a_cluster_is_one_error_line(tmp_path, monkeypatch):
    pytest.importorskip("ray", reason="Ray is not installed (pip install ray)")
    if os.path.exists("/tmp/ray/ray_current_cluster"):
        pytest.skip("a Ray cluster runs on this machine: 'auto' would join it")
    monkeypatch.delenv("RAY_ADDRESS", raising=False)
    out = tmp_path / "auto"
    code = corps_learn.main([CAMPAIGN, "--iterations", "1", "--repeats", "1", "-o", str(out),
                             "--ray", "auto"])
    assert code == 1
    assert not out.exists()


def test_a_failing_map_stops_the_campaign_which_resumes_to_the_same_end(reference, tmp_path):
    here = lambda jobs: [corps._corps.learning_rollout(CAMPAIGN, TEXT, job) for job in jobs]
    counted = []
    corps._corps.learn(CAMPAIGN, 2, 2, None, str(tmp_path / "count"),
                       lambda jobs: counted.append(len(jobs)) or here(jobs), "a counting map")
    # The map's last call is the tests' batch; the cluster "goes away" on the last training one.
    last_training = len(counted) - 1
    out = tmp_path / "resumed"
    calls = []

    def flaky(jobs):
        calls.append(len(jobs))
        if len(calls) >= last_training:
            raise ConnectionError("the cluster went away")
        return here(jobs)

    with pytest.raises(corps.ScenarioError, match="running rollouts: .*the cluster went away"):
        corps._corps.learn(CAMPAIGN, 2, 2, None, str(out), flaky, "a flaky map")
    # Every row written is whole and one the uninterrupted campaign writes; the rerun replays
    # them and runs the rest.
    written = (out / "evaluations.csv").read_text()
    assert written.endswith("\n")
    kept = written.splitlines()[1:]
    assert kept, "no evaluation was kept"
    assert set(kept) <= set(reference["evaluations"][1:])
    text = corps_learn.learn(CAMPAIGN, iterations=2, repeats=2, output=str(out))
    assert f"{len(kept)} evaluations replayed" in text, text
    assert files(out) == reference


def test_a_map_returning_too_few_results_is_an_error(tmp_path):
    with pytest.raises(corps.ScenarioError, match="results for"):
        corps._corps.learn(CAMPAIGN, 1, 1, None, str(tmp_path / "few"), lambda jobs: [],
                           "a broken map")


def test_ctrl_c_stops_a_campaign_run_from_python_and_it_resumes(tmp_path):
    import signal
    import sys
    import time

    out = tmp_path / "interrupted"
    process = subprocess.Popen(
        [sys.executable, "-m", "corps", "learn", CAMPAIGN, "--iterations", "200", "--repeats",
         "2", "-o", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    evaluations = out / "evaluations.csv"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and process.poll() is None:
        if evaluations.exists() and len(evaluations.read_text().splitlines()) >= 4:
            break
        time.sleep(0.1)
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    assert "rerun the same command to resume" in stderr
    rows = evaluations.read_text()
    assert rows.endswith("\n") and len(rows.splitlines()) >= 4
