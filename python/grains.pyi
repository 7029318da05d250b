"""grains: DEM (2D and 3D), MPM and FEM–DEM simulations of granular materials, from Python.

Open a scenario (the same TOML files `grains run` reads), step it, read its particles
as numpy arrays, add forces from Python, and write what `grains run` writes.
"""

from os import PathLike
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike]
__version__: str

class InputError(ValueError):
    """A scenario, spec or checkpoint was refused (one line: key, value, what is allowed)."""

class InternalError(RuntimeError):
    """A bug in grains (a Rust panic), with its message."""

class StaleViewError(RuntimeError):
    """A view used after the engine reordered or resized its particle storage."""

class Particles:
    """The particles in id order (copies). Fields an engine has not are None.

    2D runs: position, velocity, force (N, 2); omega, torque (N,); mass in kg/m.
    3D runs (dim == 3): position, velocity, force, omega, torque all (N, 3); mass in kg.
    """

    id: npt.NDArray[np.uint32]
    position: npt.NDArray[np.float64]
    velocity: npt.NDArray[np.float64]
    omega: Optional[npt.NDArray[np.float64]]
    radius: npt.NDArray[np.float64]
    mass: npt.NDArray[np.float64]
    force: Optional[npt.NDArray[np.float64]]
    torque: Optional[npt.NDArray[np.float64]]
    def __len__(self) -> int: ...

class View:
    """A read-only zero-copy view of a particle field in the engine's storage order.

    Raises StaleViewError once the engine reorders or resizes its storage (DEM: at a
    neighbour-list rebuild). An array taken with np.asarray(view) points into the
    engine's memory: while it (or a slice of it) is referenced, stepping raises
    RuntimeError. Keep the view, not the array.
    """

    array: npt.NDArray[Any]
    valid: bool
    name: str
    def __array__(self, dtype: Any = None, copy: Optional[bool] = None) -> npt.NDArray[Any]: ...
    def __getitem__(self, key: Any) -> Any: ...
    def __len__(self) -> int: ...

ForceResult = Union[npt.NDArray[np.float64], Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]]

class Simulation:
    """A simulation of any engine (DEM in 2D or 3D, MPM, FEM–DEM), opened from a scenario.

    Vectors have `dim` components: 2, or 3 for a 3D DEM run (`dim = 3` in the scenario).
    """

    @staticmethod
    def from_file(path: _Path) -> "Simulation":
        """Opens a scenario file; raises InputError with the command line's message."""
    @staticmethod
    def from_toml(text: str, base: Optional[_Path] = None) -> "Simulation":
        """Opens a scenario given as TOML text (relative paths from `base`)."""
    @staticmethod
    def from_dict(d: Dict[str, Any], base: Optional[_Path] = None) -> "Simulation":
        """Opens a scenario given as a dict of the TOML file's tables."""
    @staticmethod
    def resume(path: _Path) -> "Simulation":
        """Continues the run checkpointed in the directory `path`, bitwise."""
    def step(self, n: int = 1) -> None:
        """Takes n steps (the GIL released; Ctrl-C raises KeyboardInterrupt between steps)."""
    def run(
        self,
        until: Optional[float] = None,
        callback: Optional[Callable[["Simulation"], Any]] = None,
        every: int = 1,
    ) -> str:
        """Runs to the scenario's end (or time `until`), calling callback(sim) every
        `every` steps; returns "completed", "at_rest", "unstable" or "paused"."""
    time: float
    steps: int
    dt: float
    engine: str
    dim: int
    status: Optional[str]
    work_dir: str
    def state_hash(self) -> str:
        """The command line's fingerprint of the whole state (hex, as summary.json)."""
    def particles(self) -> Particles:
        """The particles in id order (copies); vectors (N, dim)."""
    def view(self, name: str) -> View:
        """A read-only zero-copy view of a particle field (storage order): id, position,
        velocity, omega, radius, force ((N, dim); omega (N, 3) in 3D); MPM: id, position,
        velocity, mass."""
    def set(self, name: str, ids: npt.ArrayLike, values: npt.ArrayLike) -> None:
        """Sets "position" or "velocity" of the particles `ids` to (k, dim) float64
        `values` (another shape or dtype: ValueError naming the array and both shapes)."""
    def add_force(self, fn: Callable[["Simulation"], ForceResult]) -> None:
        """fn(sim) returns (N, dim) forces in id order, or (forces, torques) with torques
        (N,) in 2D and (N, 3) in 3D, added every step after the contact forces (DEM in 2D
        and 3D, FEM–DEM)."""
    def contacts(self) -> Dict[str, npt.NDArray[Any]]:
        """Touching pairs: i, j (ids), overlap, and on i normal_force, tangential_force,
        and branch (i's centre to j's), each (M, dim)."""
    def points(self) -> Dict[str, npt.NDArray[Any]]:
        """MPM points: id, body, position, velocity, mass, volume, stress."""
    def charge(self) -> Dict[str, npt.NDArray[Any]]:
        """FEM–DEM charge: node position and velocity, triangles, pressure."""
    def history(self) -> Dict[str, npt.NDArray[np.float64]]:
        """The history so far, as history.csv's columns."""
    def summary(self) -> Dict[str, Any]:
        """Ends the run and returns summary.json as a dict."""
    def write(self, out: _Path) -> None:
        """Ends the run and writes what `grains run` writes into `out`."""
    def checkpoint(self, path: _Path) -> None:
        """Writes a resumable run directory (DEM in 2D and 3D, FEM–DEM)."""

def run(path: _Path, out: Optional[_Path] = None, threads: Optional[int] = None) -> Dict[str, Any]:
    """Runs a scenario file as `grains run` does; returns the summary."""

def pack(spec: _Path, out: Optional[_Path] = None) -> Dict[str, Any]:
    """Makes a packing as `grains pack` does; figures plus position and radius arrays."""

def analyze(path: _Path, out: Optional[_Path] = None) -> Dict[str, Any]:
    """Analyses a run directory, a packing file or a frame as `grains analyze` does."""
