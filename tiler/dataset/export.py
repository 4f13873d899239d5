"""Export datasets as a static IIIF level-0 tree for any web server or object storage.

``export(source, out, base_url)`` writes the folder ``out``, to be published at ``base_url``: each
dataset of ``source`` (one dataset folder, or a data root of several) becomes ``out/NAME/`` with
every URL that starts with the dataset's recorded ``baseUrl`` rewritten to start with
``base_url`` instead (manifest, canvas, annotation page and annotation ids, image service ids in
``info.json`` and in the manifest, relight and overlay service blocks, ``lanterna.json``'s
``baseUrl`` …). Everything else is hard-linked (copied when linking is impossible), so the
export of a large dataset costs little space and time. No server is needed to use the result.

The tree is built in a temporary folder beside ``out`` and swapped into place when complete; on
any error nothing is left behind and an existing ``out`` is untouched. Each dataset is read from
one version, held for the time it is copied (:func:`~.publish.reading`), so an export never
mixes the files of two versions when the dataset is rewritten meanwhile. Datasets that are links
to a version folder are exported as plain folders.
"""

from __future__ import annotations

import html
import json
import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn
from urllib.parse import quote, urlsplit

from lanterna.errors import LanternaInputError
from lanterna.manifests.validate import validate_manifest

from .output import json_text, write_errors
from .publish import list_datasets, new_temp, reading, replace_folder, writing
from .writer import link_or_copy, read_description


@dataclass
class ExportReport:
    """What :func:`export` wrote: dataset names, manifest URLs and file counts."""

    out: Path
    base_url: str
    manifests: dict[str, str] = field(default_factory=dict)
    linked: int = 0
    copied: int = 0
    rewritten: int = 0
    viewer: str | None = None


def check_base_url(url: str) -> str:
    """Return ``url`` without a trailing slash if it is an absolute http(s) URL, else raise.

    IIIF ids must be HTTP(S) URIs (the Presentation 3.0 schema requires ``^http``), and the base
    URL is a prefix, so it may not carry a query or a fragment.
    """
    parts = urlsplit(url)
    if parts.scheme not in ("http", "https") or not parts.netloc or parts.query or parts.fragment:
        raise LanternaInputError(None, f"--base-url must be an absolute http(s) URL without query "
                                 f"or fragment, such as https://example.org/iiif; got {url!r}")
    return url.rstrip("/")


def find_datasets(source: Path) -> list[Path]:
    """Return the dataset folders of ``source``: itself if it is a dataset, else its children.

    Raises
    ------
    LanternaInputError
        If ``source`` is missing, not a folder, or holds no dataset.
    """
    if not source.exists():
        raise LanternaInputError(source, "no such folder")
    if not source.is_dir():
        raise LanternaInputError(source, "not a folder (give a dataset folder or a data root)")
    if (source / "lanterna.json").is_file():
        return [source]
    found = list_datasets(source)
    if not found:
        raise LanternaInputError(source, "not a Lanterna dataset or data root (no lanterna.json "
                                 "in it or in its sub-folders)")
    return found


def export(source: Path, out: Path, base_url: str, *, force: bool = False,
           viewer: Path | None = None) -> ExportReport:
    """Write the static tree of ``source``'s datasets to ``out``, to be published at ``base_url``.

    Parameters
    ----------
    source
        A dataset folder (with ``lanterna.json``) or a data root holding dataset folders.
    out
        The folder to create; dataset ``NAME`` goes to ``out/NAME``.
    base_url
        The absolute http(s) URL ``out`` will be published at.
    force
        Replace an existing ``out``.
    viewer
        A built viewer folder (``plugin/dist/viewer``) to copy to ``out/viewer``, with an
        ``out/index.html`` linking each dataset in it; ``None`` exports the datasets only.

    Returns
    -------
    ExportReport
        Manifest URL per dataset name and file counts.
    """
    base = check_base_url(base_url)
    source, out = Path(source), Path(out)
    datasets = find_datasets(source)
    _check_output(source, out, force)
    if viewer is not None and not (viewer / "index.html").is_file():
        raise LanternaInputError(viewer, "the viewer is not built (run `npm run build`)")
    report = ExportReport(out, base)
    with write_errors(out):
        out.parent.mkdir(parents=True, exist_ok=True)
    with writing(out):
        if out.exists() and not force:  # made by another export since the check above
            raise LanternaInputError(out, "output exists (use --force to replace it)")
        tmp = new_temp(out)
        try:
            with write_errors(out):
                for folder in datasets:
                    with reading(folder) as version:
                        _export_dataset(folder, version, tmp, base, report)
                if viewer is not None:
                    shutil.copytree(viewer, tmp / "viewer")
                    (tmp / "index.html").write_text(_index_html(report))
                    report.viewer = f"{base}/viewer/"
                replace_folder(tmp, out)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return report


def _check_output(source: Path, out: Path, force: bool) -> None:
    src, dst = source.resolve(), out.resolve()
    if dst == src or dst in src.parents or src in dst.parents:
        raise LanternaInputError(out, f"the output may not contain, or be inside, {source}")
    if out.exists() and not force:
        raise LanternaInputError(out, "output exists (use --force to replace it)")
    if out.exists() and not out.is_dir():
        raise LanternaInputError(out, "output exists and is not a folder")


def _export_dataset(folder: Path, version: Path, tmp: Path, base: str,
                    report: ExportReport) -> None:
    """Copy the dataset ``folder``, whose files are in ``version``, to ``tmp/NAME``."""
    desc = read_description(version)
    name, old = str(desc.get("name", "")), str(desc.get("baseUrl", "")).rstrip("/")
    if not name or not old:
        raise LanternaInputError(folder / "lanterna.json", "has no name or baseUrl")
    if name in report.manifests:
        raise LanternaInputError(folder, f"two datasets are named {name!r}")
    target = tmp / name
    for dirpath, _dirs, files in os.walk(version, onerror=_unreadable):
        here = Path(dirpath)
        dest = target / here.relative_to(version)
        dest.mkdir(parents=True, exist_ok=True)
        for file in files:
            if file.endswith(".json"):
                shown = report.out / name / here.relative_to(version) / file
                _rewrite_json(here / file, dest / file, old, base, shown)
                report.rewritten += 1
            elif link_or_copy(here / file, dest / file):
                report.linked += 1
            else:
                report.copied += 1
    manifest = json.loads((target / "manifest.json").read_text())
    errors = validate_manifest(manifest)
    if errors:
        raise LanternaInputError(folder / "manifest.json", "the exported manifest is not valid "
                                 f"IIIF Presentation 3.0: {errors[0]}")
    report.manifests[name] = str(manifest["id"])


def _unreadable(err: OSError) -> NoReturn:
    raise LanternaInputError(err.filename, f"cannot read ({err.strerror})")


def _rewrite_json(src: Path, dst: Path, old: str, new: str, shown: Path) -> None:
    try:
        text = src.read_text()
    except OSError as err:
        _unreadable(err)
    try:
        doc = json.loads(text)
    except ValueError as err:
        raise LanternaInputError(src, f"not valid JSON ({err})") from None
    ending = "\n" if text.endswith("\n") else ""
    dst.write_text(json_text(rebase(doc, old, new), shown) + ending)


def rebase(doc: Any, old: str, new: str) -> Any:
    """Return ``doc`` with every string equal to ``old``, or containing ``old + "/"``, rebased.

    Only whole URL prefixes are replaced: ``http://a/b`` is not rewritten in ``http://a/bc``.
    This is what ``lanterna serve`` does to the text of every JSON document it serves.
    """
    if isinstance(doc, str):
        return new if doc == old else doc.replace(old + "/", new + "/")
    if isinstance(doc, list):
        return [rebase(item, old, new) for item in doc]
    if isinstance(doc, dict):
        return {key: rebase(value, old, new) for key, value in doc.items()}
    return doc


def _index_html(report: ExportReport) -> str:
    rows = "\n".join(
        f'<li><a href="viewer/?manifest={html.escape(quote(url, safe=":/"))}">'
        f"{html.escape(name)}</a> "
        f'<small>(<a href="{html.escape(name)}/manifest.json">IIIF manifest</a>)</small></li>'
        for name, url in report.manifests.items())
    return ("<!doctype html><meta charset=utf-8><title>Lanterna</title>"
            "<style>body{font:16px system-ui;margin:2em;max-width:50em}</style>"
            f"<h1>Lanterna</h1><ul>\n{rows}\n</ul>\n")
