"""corps: whole-body control for humanoid robots, from Rust.

Pinocchio's conventions and names (snake_case), so that habits carry over::

    import corps, numpy as np
    model = corps.Model.from_urdf("talos_reduced.urdf", floating_base=True)
    data = model.create_data()
    q = corps.neutral(model)
    tau = corps.rnea(model, data, q, np.zeros(model.nv), np.zeros(model.nv))

- q of a free-flyer is [x, y, z, qx, qy, qz, qw, joints...] (m, unit quaternion, rad);
  v is [linear (base frame, m/s), angular (base frame, rad/s), joints...].
- Spatial vectors and Jacobian rows are [linear; angular]; reference frames LOCAL, WORLD,
  LOCAL_WORLD_ALIGNED as in Pinocchio.
- Joints are in Pinocchio's depth-first order; `model.joint_names` has no "universe".
- Functions return new arrays (never views that the next call overwrites) and also keep the
  result in `data` (data.M, data.tau, data.com, ...).

Closed-loop runs of corps' scenario files::

    result = corps.run("scenarios/icub/fsm2_stepping.toml", duration=5.0)
    result["com_z"], result.metrics["verdict"], result.dataframe()

A Python class can be the plant of a run (another engine, a robot bridge): see `corps.Plant`.

Errors are `corps.CorpsError` (subclasses `ModelError`, `ScenarioError`, `PlantError`) with the
one-line message the `corps` command prints.
"""

from ._corps import (  # noqa: F401
    LOCAL,
    LOCAL_WORLD_ALIGNED,
    WORLD,
    CorpsError,
    Command,
    Data,
    Model,
    ModelError,
    PlantError,
    ReferenceFrame,
    RunResult,
    ScenarioError,
    SE3,
    __version__,
    aba,
    center_of_mass,
    centroidal_map,
    compute_centroidal_momentum,
    compute_frame_jacobian,
    compute_generalized_gravity,
    compute_joint_jacobians,
    compute_kinetic_energy,
    compute_minverse,
    compute_potential_energy,
    crba,
    difference,
    forward_kinematics,
    frame_placement,
    get_frame_jacobian,
    integrate,
    jacobian_center_of_mass,
    neutral,
    nonlinear_effects,
    random_configuration,
    rnea,
    run,
)

from .plant import Plant  # noqa: E402

__all__ = [name for name in dir() if not name.startswith("_")] + ["__version__"]
