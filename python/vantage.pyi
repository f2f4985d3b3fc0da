"""Type stubs of the vantage module (python/vantage_module.cpp; docs/python.md).

Lengths are metres, option angles degrees, quaternions [w, x, y, z]. Bad input raises
InputError (a ValueError) with the CLI's `file:line: message`; internal failures RuntimeError.
"""

import os
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt
import scipy.sparse

__version__: str

PathLike = Union[str, bytes, os.PathLike]
Paths = Union[PathLike, Sequence[PathLike], None]
Names = Union[str, Sequence[str], None]
Quality = Optional[dict[str, Optional[float]]]
Progress = Optional[Callable[[int, int], Any]]

class InputError(ValueError):
    """Bad input the user can fix; the message is the CLI's `file:line: message`."""

class Candidate:
    """One candidate sensor: a sensor type at a world pose of its body frame (x forward)."""
    @property
    def name(self) -> str: ...
    @property
    def type(self) -> str: ...
    @property
    def sensor(self) -> str: ...
    @property
    def technology(self) -> str: ...
    @property
    def population(self) -> str: ...
    @property
    def position(self) -> npt.NDArray[np.float64]:
        """(3,) [m], world."""
    @property
    def quaternion(self) -> npt.NDArray[np.float64]:
        """(4,) world_from_body, [w, x, y, z]."""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def fx(self) -> float: ...
    @property
    def fy(self) -> float: ...
    @property
    def cx(self) -> float: ...
    @property
    def cy(self) -> float: ...
    @property
    def near(self) -> float: ...
    @property
    def far(self) -> float: ...
    @property
    def cost(self) -> float: ...
    @property
    def coverage(self) -> Optional[float]:
        """Share of R it sees alone, 0..1; None before observe."""
    @property
    def observed_voxels(self) -> Optional[int]:
        """Cells of R it sees alone (its row sum of Visibility.matrix); None before observe."""
    @property
    def paper_coverage(self) -> Optional[float]:
        """|O_i| / |R|, cells outside R counted too; None before observe."""
    @property
    def rays_traced(self) -> Optional[int]: ...
    @property
    def ideal_coverage(self) -> Optional[float]:
        """Physical sensor model: the ideal pinhole's coverage; else None."""
    @property
    def plain_coverage(self) -> Optional[float]:
        """Quality filter: coverage counting every pixel; else None."""
    @property
    def target_pixels(self) -> Optional[int]: ...
    @property
    def quality_pixels(self) -> Optional[int]: ...

class Selection:
    """A chosen constellation and how good it is."""
    @property
    def method(self) -> str: ...
    @property
    def n(self) -> int: ...
    @property
    def sensors(self) -> list[str]: ...
    @property
    def indices(self) -> list[int]: ...
    @property
    def coverage(self) -> float: ...
    @property
    def paper_coverage(self) -> float: ...
    @property
    def upper_bound(self) -> Optional[float]: ...
    @property
    def optimal(self) -> bool: ...
    @property
    def objective(self) -> str: ...
    @property
    def k(self) -> int: ...
    @property
    def goal(self) -> Optional[float]: ...
    @property
    def budget(self) -> Optional[float]: ...
    @property
    def cost(self) -> Optional[float]: ...
    @property
    def n_lower_bound(self) -> Optional[int]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def gap(self) -> Optional[float]:
        """upper_bound - coverage where a bound is proven."""
    @property
    def min_points(self) -> Optional[int]: ...
    @property
    def cost_lower_bound(self) -> Optional[float]: ...
    @property
    def ideal_coverage(self) -> Optional[float]:
        """Physical sensor model: the same sensors under the ideal pinhole; else None."""
    @property
    def plain_coverage(self) -> Optional[float]:
        """Quality filter: the same sensors counting every pixel; else None."""
    @property
    def ceiling(self) -> Optional[float]:
        """All candidates together, counted as this result (report.json ceiling.coverage)."""
    @property
    def part_coverage(self) -> Optional[dict[str, float]]:
        """Per target part, the share of its cells covered; None when R knows no parts."""
    @property
    def constraints(self) -> Optional[dict[str, Any]]:
        """With installation constraints: report.json's result constraints."""

class Visibility:
    """The visibility matrix of an observed scene, with R and the candidates."""
    @property
    def matrix(self) -> scipy.sparse.csr_matrix:
        """(candidates, reference cells), float64, 1.0 where seen; built once."""
    @property
    def reference(self) -> npt.NDArray[np.float64]:
        """(R, 3) cell centres [m], in column order."""
    @property
    def reference_keys(self) -> npt.NDArray[np.uint64]: ...
    @property
    def cell_size(self) -> float: ...
    @property
    def candidates(self) -> list[Candidate]: ...
    @property
    def scene(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def quality(self) -> dict[str, Optional[float]]: ...
    @property
    def physical(self) -> bool:
        """Observed with the physical sensor model (False: the ideal pinhole)."""
    @property
    def exposed_only(self) -> bool: ...
    @property
    def parts(self) -> list[str]:
        """R's target parts by name, in scene order."""
    @property
    def reference_parts(self) -> Optional[npt.NDArray[np.uint32]]:
        """(R,) each cell's part (index into parts); None when R knows no parts."""
    @property
    def reference_exposed(self) -> Optional[npt.NDArray[np.bool_]]:
        """(R,) True where some viewpoint could see the cell; None when not computed."""
    def select(
        self,
        n: Optional[int] = None,
        method: str = "exact",
        time_limit: Optional[float] = None,
        k: Optional[int] = None,
        goal: Optional[float] = None,
        budget: Optional[float] = None,
        *,
        iterations: Optional[int] = None,
        stop: Optional[float] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        interference: Optional[bool] = None,
        interference_overlap: Optional[float] = None,
        calibration_overlap: Optional[int] = None,
        calibration_overlap_frac: Optional[float] = None,
        min_points: Optional[int] = None,
        min_density: Optional[float] = None,
        cheapest: bool = False,
        keep_existing: bool = False,
    ) -> Selection:
        """n sensors with one method, as `vantage select FILE -n N --method M`."""
    def select_all(
        self,
        n: Optional[int] = None,
        method: Optional[str] = None,
        time_limit: Optional[float] = None,
        k: Optional[int] = None,
        goal: Optional[float] = None,
        budget: Optional[float] = None,
        *,
        iterations: Optional[int] = None,
        stop: Optional[float] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        interference: Optional[bool] = None,
        interference_overlap: Optional[float] = None,
        calibration_overlap: Optional[int] = None,
        calibration_overlap_frac: Optional[float] = None,
        min_points: Optional[int] = None,
        min_density: Optional[float] = None,
        cheapest: bool = False,
        keep_existing: bool = False,
    ) -> list[Selection]:
        """Every result of `vantage select FILE` (report.json's results), in order."""
    def save(self, path: PathLike) -> None:
        """Writes the .vis file of `vantage observe --out`."""
    @staticmethod
    def from_matrix(
        csr: Union[
            scipy.sparse.csr_matrix,
            tuple[npt.ArrayLike, npt.ArrayLike],
            tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike],
        ],
        *,
        cells: Optional[int] = None,
        names: Optional[Sequence[str]] = None,
        costs: Optional[Union[Sequence[float], npt.NDArray[np.floating]]] = None,
        states: None = None,
    ) -> "Visibility":
        """A matrix computed elsewhere (candidates x cells; data: point counts) as a Visibility
        that select(), select_all() and save() take like a loaded .vis; states: refused."""

class Problem:
    """A loaded scene with its candidates deployed, before any ray is cast."""
    @property
    def source(self) -> str: ...
    @property
    def cell_size(self) -> float: ...
    @property
    def seed(self) -> int: ...
    @property
    def n(self) -> int: ...
    @property
    def candidates(self) -> list[Candidate]: ...
    @property
    def states(self) -> list[str]: ...
    def observe(
        self,
        quality: Quality = None,
        threads: Optional[int] = None,
        progress: Progress = None,
        *,
        cull: bool = True,
        max_memory: Optional[float] = None,
        physical: Optional[bool] = None,
        max_seconds: Optional[float] = None,
        n: Optional[int] = None,
    ) -> Visibility:
        """R and every candidate's depth image ray cast (GIL released), as `vantage observe`."""

def load(
    path: PathLike,
    *,
    model_path: Paths = None,
    resource_path: Paths = None,
    targets: Names = None,
    cell_size: Optional[float] = None,
    seed: Optional[int] = None,
    observation_point: Optional[Sequence[float]] = None,
    random_roll: Optional[bool] = None,
    package_path: Paths = None,
    exposed_only: bool = False,
) -> Problem:
    """Loads a scene (.yaml) or Gazebo world (.world/.sdf) and deploys its candidates."""

def load_visibility(path: PathLike) -> Visibility:
    """Reads a .vis file of Visibility.save() or `vantage observe --out`."""

def optimize(
    scene: PathLike,
    n: Optional[int] = None,
    method: Optional[str] = None,
    out: Optional[PathLike] = None,
    *,
    model_path: Paths = None,
    resource_path: Paths = None,
    targets: Names = None,
    cell_size: Optional[float] = None,
    seed: Optional[int] = None,
    observation_point: Optional[Sequence[float]] = None,
    random_roll: Optional[bool] = None,
    quality: Quality = None,
    cull: bool = True,
    max_memory: Optional[float] = None,
    iterations: Optional[int] = None,
    stop: Optional[float] = None,
    time_limit: Optional[float] = None,
    goal: Optional[float] = None,
    k: Optional[int] = None,
    budget: Optional[float] = None,
    over_states: Optional[str] = None,
    fov_tolerance: Optional[float] = None,
    alternatives_within: Optional[float] = None,
    refine: bool = False,
    refine_rounds: Optional[int] = None,
    threads: Optional[int] = None,
    progress: Progress = None,
    interference: Optional[bool] = None,
    interference_overlap: Optional[float] = None,
    calibration_overlap: Optional[int] = None,
    calibration_overlap_frac: Optional[float] = None,
    min_points: Optional[int] = None,
    min_density: Optional[float] = None,
    package_path: Paths = None,
    exposed_only: bool = False,
    physical: Optional[bool] = None,
    max_seconds: Optional[float] = None,
    cheapest: bool = False,
    keep_existing: bool = False,
    pose_tolerance: Optional[tuple[float, float]] = None,
    pose_samples: Optional[int] = None,
    by_type: bool = False,
    cycle_time: Optional[float] = None,
    joint_speed: Optional[float] = None,
    frames: Optional[int] = None,
    motion_resolution: Optional[float] = None,
    plan_time: Optional[float] = None,
    track: bool = False,
    move_penalty: Optional[float] = None,
    state_interval: Optional[float] = None,
    over_parts: Optional[str] = None,
) -> dict[str, Any]:
    """`vantage optimize SCENE`: the same files into `out`; returns report.json as a dict."""

def select(
    file: PathLike,
    n: Optional[int] = None,
    method: Optional[str] = None,
    out: Optional[PathLike] = None,
    *,
    iterations: Optional[int] = None,
    stop: Optional[float] = None,
    time_limit: Optional[float] = None,
    goal: Optional[float] = None,
    k: Optional[int] = None,
    budget: Optional[float] = None,
    cheapest: bool = False,
    keep_existing: bool = False,
    over_states: Optional[str] = None,
    seed: Optional[int] = None,
    fov_tolerance: Optional[float] = None,
    alternatives_within: Optional[float] = None,
    pose_tolerance: Optional[tuple[float, float]] = None,
    pose_samples: Optional[int] = None,
    threads: Optional[int] = None,
    interference: Optional[bool] = None,
    interference_overlap: Optional[float] = None,
    calibration_overlap: Optional[int] = None,
    calibration_overlap_frac: Optional[float] = None,
    min_points: Optional[int] = None,
    min_density: Optional[float] = None,
    over_parts: Optional[str] = None,
    cycle_time: Optional[float] = None,
    joint_speed: Optional[float] = None,
    frames: Optional[int] = None,
    motion_resolution: Optional[float] = None,
    plan_time: Optional[float] = None,
) -> dict[str, Any]:
    """`vantage select FILE`: the same files into `out`; returns report.json as a dict."""

def evaluate(
    scene: Optional[PathLike] = None,
    *,
    constellation: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    model_path: Paths = None,
    resource_path: Paths = None,
    targets: Names = None,
    cell_size: Optional[float] = None,
    seed: Optional[int] = None,
    quality: Quality = None,
    cull: bool = True,
    max_memory: Optional[float] = None,
    threads: Optional[int] = None,
    progress: Progress = None,
    interference: Optional[bool] = None,
    interference_overlap: Optional[float] = None,
    calibration_overlap: Optional[int] = None,
    calibration_overlap_frac: Optional[float] = None,
    min_points: Optional[int] = None,
    min_density: Optional[float] = None,
    observation_point: Optional[Sequence[float]] = None,
    random_roll: Optional[bool] = None,
    package_path: Paths = None,
    exposed_only: bool = False,
    physical: Optional[bool] = None,
    max_seconds: Optional[float] = None,
    pose_tolerance: Optional[tuple[float, float]] = None,
    pose_samples: Optional[int] = None,
) -> dict[str, Any]:
    """`vantage evaluate`: sensors, sensor_coverage, coverage, paper_coverage, report."""

def render(
    run: PathLike,
    png: Optional[PathLike] = None,
    *,
    eye: Optional[Sequence[float]] = None,
    look_at: Optional[Sequence[float]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    fov: Optional[float] = None,
    frusta: bool = True,
    from_below: bool = False,
    legend: bool = True,
    scene: Optional[PathLike] = None,
    model_path: Paths = None,
    resource_path: Paths = None,
    package_path: Paths = None,
    targets: Names = None,
    arm_view: Optional[int] = None,
    threads: Optional[int] = None,
) -> dict[str, Any]:
    """`vantage render RUN`: the PNG; returns {'png', 'sensors', 'coverage'}."""

def sensors() -> list[dict[str, Any]]:
    """The sensor catalog, the keys of `vantage sensors --json` plus depth_noise."""

def set_log_level(level: str) -> None:
    """'debug', 'info', 'warning' (default), 'error' or 'off'."""
