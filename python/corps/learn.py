"""Learning task weights from Python (seed 001 ch. 5), on this machine or on a Ray cluster.

`learn` runs a campaign file exactly as ``corps learn`` does: the same optimizer, seeds and
files (``evaluations.csv``, ``learned.csv``, ``fitness.png``, ``tests.csv``), the same resume
after an interruption. Its rollouts run on this machine's threads, or, with ``ray=ADDRESS``,
each as a Ray task calling :func:`corps._corps.learning_rollout` in a worker process. A
rollout depends only on its weights and seed, so a campaign ends with the same files
wherever its rollouts ran.

A cluster::

    ray start --head --num-cpus 8                  # on the first machine
    ray start --address HEAD_IP:6379               # on each other machine
    corps-learn campaigns/icub/phi_pr.toml --ray auto -o out/learn/phi_pr

Every machine needs this Python package installed and the campaign's files (campaign,
scenarios, robot descriptions) at the same absolute path as on the machine that runs
``corps-learn`` (the same checkout, or a shared file system). ``--ray local`` starts a Ray
instance on this machine alone (``--ray-cpus`` worker processes).
"""

import argparse
import os
import socket
import sys

from . import _corps
from ._corps import ScenarioError

__all__ = ["learn", "RayMap", "main"]


def _rollout(campaign, text, job):
    """One rollout in a Ray worker: the same call, so the same result, as on the driver."""
    from corps import _corps as native

    return native.learning_rollout(campaign, text, tuple(job))


def _check_reachable(address, timeout=5.0):
    """A Ray address `host:port` answers, or a clear error before any rollout."""
    host, sep, port = address.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    if not sep or not host or not port.isdigit():
        raise ScenarioError(
            f"--ray: '{address}' is not 'auto', 'local' or HOST:PORT (the head's address, "
            "as `ray start --head` prints it)"
        )
    try:
        socket.create_connection((host, int(port)), timeout=timeout).close()
    except OSError as e:
        raise ScenarioError(
            f"--ray: cannot reach a Ray head at {address} ({e}); start one with "
            "`ray start --head` there"
        ) from None


class RayMap:
    """Runs batches of rollouts as Ray tasks, one task per rollout.

    `address`: ``"auto"`` (the cluster this machine joined with ``ray start``), ``"local"``
    (a new Ray instance on this machine with `cpus` worker processes) or ``HOST:PORT`` (a
    head's address). Raises `ScenarioError` if Ray is not installed or the cluster cannot
    be reached.
    """

    def __init__(self, campaign, address="auto", cpus=None):
        try:
            import ray
        except ImportError:
            raise ScenarioError(
                "--ray: the `ray` package is not installed (pip install 'ray')"
            ) from None
        self._ray = ray
        self.campaign = os.path.abspath(campaign)
        try:
            with open(self.campaign, encoding="utf-8") as f:
                self._text = f.read()
        except OSError as e:
            raise ScenarioError(f"{campaign}: {e.strerror}") from None
        if cpus is not None and address != "local":
            raise ScenarioError("--ray-cpus: only with --ray local (a cluster has its own)")
        options = dict(include_dashboard=False, log_to_driver=False)
        if address == "local":
            cpus = cpus or os.cpu_count() or 1
            options.update(address="local", num_cpus=cpus)
            where = f"a local Ray instance ({cpus} workers)"
        else:
            if address != "auto":
                _check_reachable(address)
            options.update(address=address)
            where = f"the Ray cluster at {address}"
        if ray.is_initialized():
            raise ScenarioError("--ray: this Python process is already connected to Ray; "
                                "call ray.shutdown() first")
        try:
            ray.init(**options)
        except Exception as e:  # Ray raises ConnectionError, RuntimeError, ValueError, ...
            text = str(e).strip()
            first = text.splitlines()[0] if text else type(e).__name__
            raise ScenarioError(f"--ray: cannot join {address}: {first}") from None
        try:
            cpus_seen = int(ray.cluster_resources().get("CPU", 0))
            self.description = f"{where}, {cpus_seen} CPUs"
            self._text_ref = ray.put(self._text)
            self._task = ray.remote(num_cpus=1, max_retries=3)(_rollout)
        except BaseException:
            ray.shutdown()
            raise

    def __call__(self, jobs):
        refs = [self._task.remote(self.campaign, self._text_ref, job) for job in jobs]
        return self._ray.get(refs)

    def close(self):
        """Leaves the cluster (and stops a local instance)."""
        if self._ray.is_initialized():
            self._ray.shutdown()


def learn(campaign, *, iterations=None, repeats=None, seed=None, output=None, ray=None,
          ray_cpus=None):
    """Runs the campaign file `campaign` as ``corps learn`` does and returns its summary.

    `iterations`, `repeats`, `seed` replace the campaign's; `output` is the directory
    (default ``out/learn/<campaign name>``; an interrupted campaign's directory resumes it);
    `ray` is None (this machine's threads) or a Ray address (see :class:`RayMap`). Ctrl-C
    stops the campaign between two evaluations (`KeyboardInterrupt`); the same call resumes it.
    """
    kwargs = dict(iterations=iterations, repeats=repeats, seed=seed, output=output)
    # The same path wherever the rollouts run: an error naming a file reads the same.
    campaign = os.path.abspath(campaign)
    if ray is None:
        if ray_cpus is not None:
            raise ScenarioError("--ray-cpus: only with --ray local")
        return _corps.learn(campaign, **kwargs)
    cluster = RayMap(campaign, ray, ray_cpus)
    try:
        return _corps.learn(campaign, map=cluster, description=cluster.description, **kwargs)
    finally:
        cluster.close()


def main(argv=None, prog="corps-learn"):
    p = argparse.ArgumentParser(
        prog=prog,
        description="Learns a controller's task weights (seed 001 ch. 5) as `corps learn` "
        "does, its rollouts on this machine or on a Ray cluster.",
    )
    p.add_argument("campaign", help="the campaign file (TOML)")
    p.add_argument("--iterations", type=int, help="iterations per repeat (replaces the campaign's)")
    p.add_argument("--repeats", type=int, help="independent repeats (replaces the campaign's)")
    p.add_argument("--seed", type=int, help="the campaign's seed (replaces the campaign's)")
    p.add_argument("-o", "--output", help="output directory (default out/learn/<name>)")
    p.add_argument("--ray", metavar="ADDRESS",
                   help="run the rollouts on Ray: auto (the cluster `ray start` joined), "
                   "local (a new instance here) or HOST:PORT")
    p.add_argument("--ray-cpus", type=int, help="worker processes of --ray local")
    args = p.parse_args(argv)
    try:
        text = learn(args.campaign, iterations=args.iterations, repeats=args.repeats,
                     seed=args.seed, output=args.output, ray=args.ray, ray_cpus=args.ray_cpus)
    except ScenarioError as e:
        print(f"corps: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("corps: interrupted; the output directory holds every evaluation so far: rerun "
              "the same command to resume", file=sys.stderr)
        return 130
    print(text, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
