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
from vlab.dic.images import ImageError, bits_of, read_grey_scale


def load_images(reference: Path, deformed: list[Path]):
    """(reference image, [(stem, image)], {stem: bit depth} with the reference under its path), or
    DICError/ImageError naming the bad file. Every image must have the reference's size; bit
    depths may differ (ZNSSD is insensitive to a grey-level scale and offset), and are recorded."""
    ref, scale = read_grey_scale(reference)
    stems: dict[str, Path] = {}
    images, depths = [], {str(reference): bits_of(scale)}
    for path in deformed:
        if path.stem in stems:
            raise DICError(f"{path} and {stems[path.stem]} have the same stem {path.stem!r}: their fields "
                           f"would both be fields/{path.stem}.csv")
        stems[path.stem] = path
        im, im_scale = read_grey_scale(path)
        if im.shape != ref.shape:
            raise DICError(f"{path} is {im.shape[1]} × {im.shape[0]} px, the reference {reference} is "
                           f"{ref.shape[1]} × {ref.shape[0]} px: every image must have the reference's size")
        depths[path.stem] = bits_of(im_scale)
        images.append((path.stem, im))
    return ref, images, depths


def analyse(reference: Path, deformed: list[Path], settings: Settings, progress=None):
    """([(stem, field)] of every deformed image, each seeded by the previous one; the bit depths
    of load_images). DICError if no subset of the reference has texture."""
    ref, images, depths = load_images(reference, deformed)
    correlator = Correlator(ref, settings)
    if not correlator.refd.textured.any():
        raise DICError(f"{reference}: none of its {correlator.refd.textured.size} subsets of {settings.subset} × "
                       f"{settings.subset} px has texture (each is uniform, or graded in one direction only): "
                       f"DIC needs a speckle pattern in the reference")
    fields, previous = [], None
    for stem, image in images:
        start = time.perf_counter()
        previous = correlator.correlate(image, guess=previous)
        fields.append((stem, previous))
        if progress:
            progress(stem, previous, time.perf_counter() - start)
    return fields, depths


def write(dest, reference: Path, fields, settings: Settings, seconds: float, depths: dict) -> dict:
    """The folder: fields/<stem>.csv, maps/<stem>.png, dic.json (with each image's bit depth),
    index.html."""
    import json

    from vlab.report.folder import report_folder

    data = {"reference": str(reference), "settings": settings_dict(settings),
            "engine": "vlab.dic: IC-GN, affine shape function, bicubic B-spline, ZNSSD",
            "columns": list(output.COLUMNS), "bit_depth": depths, "images": {}, "timing": {"total_s": seconds}}
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
