"""Grey images in and out: 8- or 16-bit PNG or TIFF, as float64 arrays indexed [row, column].

A colour image is refused (DIC correlates grey levels; converting silently would hide which
channel was meant), as is a file Pillow cannot read as an image.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


class ImageError(ValueError):
    """An image cannot be used (exit 2); the message names the file and why."""


GREY_MODES = {"L": 255, "I;16": 65535, "I;16B": 65535, "I;16L": 65535, "I": 65535, "F": None}
SUFFIXES = (".png", ".tif", ".tiff")


def read_grey(path: Path) -> np.ndarray:
    """The grey levels of ``path`` as float64 [row, column]; ImageError naming the file if it is
    not an 8- or 16-bit grey PNG or TIFF."""
    return read_grey_scale(path)[0]


def bits_of(full_scale: float | None) -> str:
    """How a full scale reads in a message: 8-bit, 16-bit or floating-point."""
    return {255: "8-bit", 65535: "16-bit"}.get(full_scale, "floating-point")


def read_grey_scale(path: Path) -> tuple[np.ndarray, float | None]:
    """(grey levels, full scale of the file's mode: 255 for 8-bit, 65535 for 16-bit, None for a
    floating-point image), ImageError as read_grey."""
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    if not path.is_file():
        raise ImageError(f"{path}: no such file")
    try:
        with Image.open(path) as im:
            mode = im.mode
            if mode not in GREY_MODES:
                raise ImageError(f"{path}: a {mode} image; DIC needs a grey image (8- or 16-bit, "
                                 f"modes {', '.join(GREY_MODES)})")
            data = np.asarray(im, dtype=np.float64)
    except (UnidentifiedImageError, OSError, SyntaxError) as exc:
        raise ImageError(f"{path}: not a readable image ({exc})") from None
    if data.ndim != 2 or min(data.shape) < 2:
        raise ImageError(f"{path}: a {data.shape} array, not a 2-D grey image")
    if not np.isfinite(data).all():
        raise ImageError(f"{path}: holds non-finite grey levels")
    return data, GREY_MODES[mode]


def write_grey(path: Path, image: np.ndarray, bits: int = 16) -> None:
    """Write ``image`` (grey levels in [0, 2**bits - 1], rounded and clipped) as an 8- or 16-bit
    PNG or TIFF (by the suffix)."""
    from PIL import Image

    if bits not in (8, 16):
        raise ValueError(f"bits must be 8 or 16, got {bits}")
    top = 2 ** bits - 1
    levels = np.clip(np.rint(image), 0, top).astype(np.uint8 if bits == 8 else np.uint16)
    Image.fromarray(levels).save(Path(path))
