"""``vlab dic REFERENCE DEFORMED...``: DIC of a grey image pair or sequence into a report folder.

Every image is read and checked (grey 8- or 16-bit PNG or TIFF, all the reference's size, distinct
stems) and the settings checked before any correlation starts; the folder is written only when
everything is done (vlab.report.folder), so a bad input leaves nothing behind.
"""

from __future__ import annotations

import time
from pathlib import Path

from vlab.dic import output
from vlab.dic.correlate import Correlator, DICError, Settings, settings_dict
from vlab.dic.images import ImageError, read_grey


def load_images(reference: Path, deformed: list[Path]):
    """(reference image, [(stem, image)]), or DICError/ImageError naming the bad file."""
    ref = read_grey(reference)
    stems: dict[str, Path] = {}
    images = []
    for path in deformed:
        if path.stem in stems:
            raise DICError(f"{path} and {stems[path.stem]} have the same stem {path.stem!r}: their fields "
                           f"would both be fields/{path.stem}.csv")
        stems[path.stem] = path
        im = read_grey(path)
        if im.shape != ref.shape:
            raise DICError(f"{path} is {im.shape[1]} × {im.shape[0]} px, the reference {reference} is "
                           f"{ref.shape[1]} × {ref.shape[0]} px: every image must have the reference's size")
        images.append((path.stem, im))
    return ref, images


def analyse(reference: Path, deformed: list[Path], settings: Settings, progress=None):
    """The fields of every deformed image (each seeded by the previous one) and their summaries."""
    ref, images = load_images(reference, deformed)
    correlator = Correlator(ref, settings)
    fields, previous = [], None
    for stem, image in images:
        start = time.perf_counter()
        previous = correlator.correlate(image, guess=previous)
        fields.append((stem, previous))
        if progress:
            progress(stem, previous, time.perf_counter() - start)
    return fields


def write(dest, reference: Path, fields, settings: Settings, seconds: float) -> dict:
    """The folder: fields/<stem>.csv, maps/<stem>.png, dic.json, index.html."""
    import json

    from vlab.report.folder import report_folder

    data = {"reference": str(reference), "settings": settings_dict(settings),
            "engine": "vlab.dic: IC-GN, affine shape function, bicubic B-spline, ZNSSD",
            "columns": list(output.COLUMNS), "images": {}, "timing": {"total_s": seconds}}
    with report_folder(dest, "dic") as tmp:
        (tmp / "fields").mkdir()
        (tmp / "maps").mkdir()
        for stem, field in fields:
            output.write_csv(tmp / "fields" / f"{stem}.csv", field)
            output.plot_maps(tmp / "maps" / f"{stem}.png", field, f"{stem} against {reference.name}")
            data["images"][stem] = output.summary(field)
        (tmp / "dic.json").write_text(json.dumps(data, indent=2), encoding="utf-8")
        output.write_index(tmp / "index.html", data)
    return data


__all__ = ["analyse", "write", "load_images", "DICError", "ImageError", "Settings"]
