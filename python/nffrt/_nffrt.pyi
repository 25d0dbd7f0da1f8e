"""Type stubs of the compiled module ``nffrt._nffrt`` (python/src/), re-exported
by ``nffrt``. Keep in step with the Rust signatures."""

import os
from typing import Literal, Optional, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

Vec3 = Tuple[float, float, float]
StrPath = Union[str, "os.PathLike[str]"]

class SceneError(ValueError):
    """A malformed scene: ``str(e)`` is ``PATH:LINE:COLUMN: what``."""

    path: Optional[str]
    """The scene file, or ``None`` for text given to ``parse``."""
    line: int
    """1-based line of the offending token."""
    column: int
    """1-based column of the offending token."""
    message: str
    """What is wrong, without the location."""

class Stats(TypedDict):
    eye_rays: int
    eye_hits: int
    reflection_rays: int
    refraction_rays: int
    secondary_hits: int
    shadow_rays: int
    shadow_blocked: int
    total_rays: int
    render_s: float

class Counts(TypedDict):
    spheres: int
    moving_spheres: int
    cones: int
    polygons: int
    patches: int
    planes: int
    boxes: int
    meshes: int
    mesh_triangles: int
    primitives: int
    lights: int
    materials: int

Camera = TypedDict(
    "Camera",
    {
        "from": Vec3,
        "at": Vec3,
        "up": Vec3,
        "angle": float,
        "hither": float,
        "width": int,
        "height": int,
        "aperture": float,
        "focal": float,
    },
)

class Light(TypedDict, total=False):
    position: Vec3
    color: Optional[Vec3]
    v1: Vec3
    v2: Vec3
    grid: int

class Scene:
    """A parsed scene and its acceleration structure, built once."""

    def render(
        self,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        max_depth: Optional[int] = None,
        region: Optional[Tuple[int, int, int, int]] = None,
        threads: Optional[int] = None,
        spd: bool = False,
        aperture: Optional[float] = None,
        focal: Optional[float] = None,
        light_samples: Optional[int] = None,
        seed: Optional[int] = None,
        integrator: Optional[str] = None,
        denoise: Union[bool, str, None] = None,
        frame: Optional[int] = None,
        time: Optional[float] = None,
    ) -> npt.NDArray[np.float32]:
        """Renders into a new ``float32`` array of shape ``(H, W, 3)``, top row first:
        linear RGB, the values ``nffrt render -o X.pfm`` writes. An argument left
        out takes what ``nffrt render`` takes without its flag: ``width``,
        ``height`` and ``spp`` the file's (one side given, the other keeps its
        aspect), ``max_depth`` 5; ``region=(x0, y0, x1, y1)`` renders that crop only;
        ``light_samples`` samples every area light on an N x N grid at every hit;
        ``seed`` chooses another, as deterministic, sample pattern (0: the usual
        one); ``integrator`` is ``"whitted"`` or ``"path"`` (default: the file's);
        ``denoise=True`` (or ``"fast"``, ``"balanced"``, ``"high"``) denoises the
        whole picture with Intel Open Image Denoise (``OSError`` without it:
        ``pip install pyoidn``). An AFF scene renders frame 0 unless ``frame`` (0 to
        ``frames - 1``) or ``time`` asks for another, as ``nffrt render
        --frame``/``--time`` does (``ValueError`` for a scene that does not move).
        Releases the GIL; Ctrl-C raises ``KeyboardInterrupt``."""
    def image_size(self, width: Optional[int] = None, height: Optional[int] = None) -> Tuple[int, int]:
        """The ``(width, height)`` ``render`` makes with these arguments."""
    @property
    def last_stats(self) -> Optional[Stats]:
        """Ray counts and time of the last finished render."""
    @property
    def path(self) -> Optional[str]:
        """The file loaded, or the ``path`` given to ``parse``; ``None`` for text."""
    @property
    def text(self) -> Optional[Union[str, bytes]]:
        """The text ``parse`` was given (``None`` for a loaded file)."""
    @property
    def format(self) -> str:
        """``"nff"``, ``"p3f-2019"``, ``"p3f-2025"`` or ``"aff"``."""
    @property
    def frames(self) -> Optional[int]:
        """An AFF scene's number of frames; ``None`` for a scene that does not move."""
    def frame_time(self, n: int) -> float:
        """The time of an AFF scene's frame ``n``."""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def spp(self) -> Optional[int]: ...
    @property
    def counts(self) -> Counts: ...
    @property
    def camera(self) -> Camera: ...
    @property
    def lights(self) -> list[Light]: ...
    @property
    def background(self) -> Vec3: ...
    @property
    def bounds(self) -> Optional[Tuple[Vec3, Vec3]]: ...
    @property
    def warnings(self) -> list[Tuple[int, int, str]]:
        """``(line, column, message)`` of what the parser tolerated."""
    def _repr_png_(self) -> bytes:
        """A preview at most 256 pixels on a side, as PNG (Jupyter)."""

def load(path: StrPath, format: Optional[str] = None) -> Scene:
    """Reads and prepares a scene file (``format``: ``"nff"``, ``"p3f"``, ``"aff"`` or by the
    extension). Raises ``SceneError`` or ``OSError``."""

def parse(
    text: Union[str, bytes], format: Optional[str] = None, path: Optional[StrPath] = None
) -> Scene:
    """Parses and prepares scene text (``format``: ``"nff"``, ``"p3f"``, ``"aff"`` or by
    ``path``'s extension, else NFF); ``path`` names the file the text is (in errors,
    and for the folder of its skybox). Raises ``SceneError``."""

def gen(name: str, size: Optional[int] = None) -> str:
    """An SPD scene (balls, gears, mount, rings, teapot, tetra, tree) as NFF text."""

def save(array: npt.ArrayLike, path: StrPath) -> None:
    """Writes an ``(H, W, 3)`` image as PNG, PPM, PFM or OpenEXR, by the extension."""

def to_png(array: npt.ArrayLike) -> bytes:
    """The PNG bytes ``save`` would write."""

def bands(width: int, height: int, n: int) -> list[Tuple[int, int, int, int]]:
    """``n`` bands of whole rows, as ``(x0, y0, x1, y1)``."""

Picture = Union[StrPath, npt.ArrayLike]
Metric = Literal["flip", "mse", "rmse", "relmse", "mae", "psnr"]

def diff(
    test: Picture, ref: Picture, metric: Metric = "flip", map: bool = False
) -> Union[float, Tuple[float, npt.NDArray[np.float32]]]:
    """How far ``test`` is from ``ref`` (paths or ``(H, W, 3)`` arrays: ``uint8``
    for 8-bit pictures, floats for linear values): FLIP's mean error, or the
    metric's value (PSNR in dB); with ``map=True`` the tuple of that value and each
    pixel's error, ``(H, W)`` ``float32``. Raises ``ValueError`` for pictures of
    different sizes or kinds, ``OSError`` for a file that cannot be read."""
