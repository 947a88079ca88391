"""Type stubs of corps' native module. Units: m, rad, s, kg, N, N·m. Configurations follow
Pinocchio: a free-flyer's q is [x, y, z, qx, qy, qz, qw], its v [linear; angular] in the base
frame; spatial vectors and Jacobian rows are [linear; angular]."""

from enum import Enum
from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

Vector = npt.NDArray[np.float64]
Matrix = npt.NDArray[np.float64]
ArrayLike = Union[npt.ArrayLike, Sequence[float]]
Path = Union[str, PathLike]
Frame = Union[int, str]

class CorpsError(Exception):
    """Base class of every error corps raises."""

class ModelError(CorpsError):
    """A model could not be loaded, or an algorithm got bad input."""

class ScenarioError(CorpsError):
    """A scenario could not be read, built or run (the `corps` command's message)."""

class PlantError(CorpsError):
    """A Python plant broke its protocol."""

class ReferenceFrame(Enum):
    """The frame a Jacobian is expressed in (Pinocchio's ReferenceFrame)."""

    LOCAL = 0
    WORLD = 1
    LOCAL_WORLD_ALIGNED = 2

LOCAL: ReferenceFrame
WORLD: ReferenceFrame
LOCAL_WORLD_ALIGNED: ReferenceFrame

class SE3:
    """A rigid placement x_a = R x_b + p."""

    def __init__(self, rotation: Matrix, translation: Vector) -> None: ...
    @staticmethod
    def Identity() -> SE3: ...
    @property
    def rotation(self) -> Matrix:
        """3 × 3 rotation matrix."""
    @property
    def translation(self) -> Vector:
        """Translation (m)."""
    @property
    def homogeneous(self) -> Matrix:
        """4 × 4 homogeneous matrix."""
    def inverse(self) -> SE3: ...
    def act(self, point: ArrayLike) -> Vector:
        """The image R p + t of a point (m)."""
    def __mul__(self, other: SE3) -> SE3: ...

class Model:
    """An immutable robot model (joints in Pinocchio's depth-first order)."""

    @staticmethod
    def from_urdf(path: Path, srdf: Optional[Path] = None, floating_base: bool = True) -> Model:
        """Loads a URDF; `floating_base` adds the free-flyer `root_joint`; `srdf` adds its
        group_states as reference configurations."""
    @staticmethod
    def from_robot(robot: str) -> Model:
        """A robot description's model: `talos`, `icub`, `icub_backpacked`,
        `simple_humanoid` or a description file. Locked joints are not in it."""
    def create_data(self) -> Data:
        """A workspace for the algorithms (Pinocchio's createData)."""
    @property
    def name(self) -> str: ...
    @property
    def nq(self) -> int:
        """Configuration size."""
    @property
    def nv(self) -> int:
        """Velocity size."""
    @property
    def njoints(self) -> int:
        """Moving joints (no universe)."""
    @property
    def nframes(self) -> int: ...
    @property
    def joint_names(self) -> List[str]:
        """Pinocchio's model.names[1:]."""
    @property
    def frame_names(self) -> List[str]: ...
    @property
    def idx_qs(self) -> List[int]: ...
    @property
    def idx_vs(self) -> List[int]: ...
    @property
    def lower_position_limit(self) -> Vector: ...
    @property
    def upper_position_limit(self) -> Vector: ...
    @property
    def velocity_limit(self) -> Vector: ...
    @property
    def effort_limit(self) -> Vector: ...
    @property
    def gravity(self) -> Vector:
        """World gravity (m/s²)."""
    @property
    def reference_configurations(self) -> List[str]: ...
    def total_mass(self) -> float:
        """kg."""
    def get_frame_id(self, name: str) -> int: ...
    def exists_frame(self, name: str) -> bool: ...
    def get_joint_id(self, name: str) -> int:
        """0-based index among the moving joints."""
    def frame_parent_joint(self, frame: Frame) -> Optional[int]:
        """The moving joint carrying `frame`; None for a frame fixed to the world."""
    def reference_configuration(self, name: str) -> Vector: ...
    def bodies(self) -> List[Dict[str, Any]]:
        """Per moving joint and its body, parents first: name, parent, kind (free, revolute,
        continuous, prismatic), axis, placement (4 × 4 in the parent joint's frame), idx_q,
        idx_v, mass (kg), com (m), inertia (3 × 3 about the CoM, kg·m²), effort."""
    def collisions(self) -> List[Dict[str, Any]]:
        """Collision primitives (meshes left out): link, joint, placement (4 × 4 in the joint's
        frame), shape (box: size; cylinder: radius, length; sphere: radius), in m."""
    def frame_attachment(self, frame: Frame) -> Tuple[Optional[int], SE3]:
        """The moving joint carrying `frame` and its placement in that joint's frame."""

class Data:
    """The algorithms' workspace; attributes are copies of the last results."""

    @property
    def tau(self) -> Vector: ...
    @property
    def nle(self) -> Vector: ...
    @property
    def g(self) -> Vector: ...
    @property
    def ddq(self) -> Vector: ...
    @property
    def M(self) -> Matrix:
        """Joint-space inertia, both triangles."""
    @property
    def Minv(self) -> Matrix: ...
    @property
    def com(self) -> Vector:
        """Centre of mass (m, world): Pinocchio's data.com[0]."""
    @property
    def vcom(self) -> Vector: ...
    @property
    def acom(self) -> Vector: ...
    @property
    def Jcom(self) -> Matrix: ...
    @property
    def Ag(self) -> Matrix: ...
    @property
    def J(self) -> Matrix: ...
    @property
    def oMi(self) -> List[SE3]:
        """World placements of the moving joints (Pinocchio's oMi[1:])."""

class Command:
    """A controller's command for one control period (given to a Python plant's step)."""

    @property
    def kind(self) -> str:
        """'torque', 'position' or 'velocity'."""
    @property
    def torque(self) -> Optional[Vector]:
        """Joint torques (N·m, size nv - 6)."""
    @property
    def q_ref(self) -> Optional[Vector]:
        """A full configuration whose joint part is the position target."""
    @property
    def v_ref(self) -> Optional[Vector]:
        """Joint velocity targets (rad/s, size nv - 6)."""

class RunResult:
    """A run's time series (one row per control tick), metrics and verdict."""

    columns: List[str]
    data: Matrix
    verdict: str
    expected: str
    metrics: Dict[str, Any]
    report: str
    @property
    def time(self) -> Vector:
        """Controlled time (s)."""
    def __getitem__(self, column: str) -> Vector: ...
    def __len__(self) -> int: ...
    def dataframe(self) -> Any:
        """The time series as a pandas.DataFrame (needs pandas)."""

def rnea(model: Model, data: Data, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> Vector:
    """τ = M(q) a + C(q, v) v + g(q)."""
def nonlinear_effects(model: Model, data: Data, q: ArrayLike, v: ArrayLike) -> Vector:
    """h(q, v) = C(q, v) v + g(q)."""
def compute_generalized_gravity(model: Model, data: Data, q: ArrayLike) -> Vector: ...
def crba(model: Model, data: Data, q: ArrayLike) -> Matrix:
    """M(q), both triangles filled (Pinocchio fills the upper)."""
def compute_minverse(model: Model, data: Data, q: ArrayLike) -> Matrix:
    """M(q)⁻¹, both triangles filled."""
def aba(model: Model, data: Data, q: ArrayLike, v: ArrayLike, tau: ArrayLike) -> Vector:
    """a = M⁻¹(τ − h)."""
def forward_kinematics(model: Model, data: Data, q: ArrayLike, v: Optional[ArrayLike] = None,
                       a: Optional[ArrayLike] = None) -> None: ...
def frame_placement(model: Model, data: Data, frame: Frame) -> SE3:
    """World placement of a frame after forward_kinematics."""
def compute_joint_jacobians(model: Model, data: Data, q: ArrayLike) -> Matrix: ...
def compute_frame_jacobian(model: Model, data: Data, q: ArrayLike, frame: Frame,
                           reference_frame: ReferenceFrame = ...) -> Matrix:
    """6 × nv Jacobian of a frame in LOCAL (default), WORLD or LOCAL_WORLD_ALIGNED."""
def get_frame_jacobian(model: Model, data: Data, frame: Frame,
                       reference_frame: ReferenceFrame = ...) -> Matrix:
    """As compute_frame_jacobian, after compute_joint_jacobians at the same q."""
def center_of_mass(model: Model, data: Data, q: ArrayLike, v: Optional[ArrayLike] = None,
                   a: Optional[ArrayLike] = None) -> Vector: ...
def jacobian_center_of_mass(model: Model, data: Data, q: ArrayLike) -> Matrix: ...
def centroidal_map(model: Model, data: Data, q: ArrayLike) -> Matrix:
    """A_G (6 × nv) about the CoM, world axes (Pinocchio's computeCentroidalMap)."""
def compute_centroidal_momentum(model: Model, data: Data, q: ArrayLike, v: ArrayLike) -> Vector: ...
def compute_kinetic_energy(model: Model, data: Data, q: ArrayLike, v: ArrayLike) -> float: ...
def compute_potential_energy(model: Model, data: Data, q: ArrayLike) -> float: ...
def neutral(model: Model) -> Vector: ...
def integrate(model: Model, q: ArrayLike, v: ArrayLike) -> Vector:
    """q ⊕ v (the quaternion kept in q's hemisphere, as Pinocchio)."""
def difference(model: Model, q0: ArrayLike, q1: ArrayLike) -> Vector:
    """q1 ⊖ q0."""
def random_configuration(model: Model, seed: Optional[int] = None) -> Vector: ...
def run(scenario: Path, robot: Optional[str] = None, duration: Optional[float] = None,
        estimator: Optional[str] = None, noise: Optional[Path] = None,
        plant: Optional[Any] = None) -> RunResult:
    """Runs a scenario file as `corps run` does, in memory; `plant` replaces the simulator."""
def learn(campaign: Path, iterations: Optional[int] = None, repeats: Optional[int] = None,
          seed: Optional[int] = None, output: Optional[Path] = None,
          map: Optional[Any] = None, description: Optional[str] = None) -> str:
    """Runs a learning campaign as `corps learn` does (same files, same resume) and returns its
    summary; `map(jobs) -> results`, if given, runs each batch of rollouts (`corps.learn`)."""
def learning_rollout(campaign: Path, text: str,
                     job: Tuple[Optional[int], Sequence[float], int]
                     ) -> Tuple[float, float, float, bool, Optional[str], int, str]:
    """One rollout of a campaign (`text`: the campaign file's text as the driver read it),
    `job` = (test run or None, weights, seed), run here: what a cluster's worker runs. Returns
    (fitness, joint-limit constraint, torque constraint, failed, error, steps, verdict)."""
