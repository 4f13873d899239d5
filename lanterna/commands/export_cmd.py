"""``lanterna export``: a static IIIF level-0 tree for any web server or object storage."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import SubParsers

EXPORT_EXAMPLES = """examples:
  lanterna export datasets/obj --base-url https://cdn.example.org/iiif -o site
      site/obj/manifest.json, to be published as https://cdn.example.org/iiif/obj/manifest.json
  lanterna export datasets/ --base-url https://example.org/rti -o site --with-viewer
      every dataset of a data root, plus the viewer at https://example.org/rti/viewer/ and an
      index page

Every IIIF id is rewritten to start with --base-url; other files are hard-linked (copied across
file systems). The tree is written beside the output and renamed into place when complete.
Deployment (nginx, object storage, CORS): docs/deploy.md.
"""


def register(sub: SubParsers) -> None:
    exp = sub.add_parser("export", help="write a static IIIF tree to publish at a given URL",
                         epilog=EXPORT_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    exp.add_argument("source", type=Path, metavar="DATASET",
                     help="a dataset folder, or a data root holding several")
    exp.add_argument("--base-url", required=True, metavar="URL",
                     help="absolute http(s) URL the output folder will be published at")
    exp.add_argument("-o", "--output", type=Path, required=True, metavar="DIR",
                     help="folder to create (dataset NAME goes to DIR/NAME)")
    exp.add_argument("--with-viewer", action="store_true",
                     help="also copy the built viewer to DIR/viewer and write DIR/index.html")
    exp.add_argument("--force", action="store_true", help="replace an existing output")
    exp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lanterna.tiler.dataset.export import export

    viewer = None
    if args.with_viewer:
        from lanterna.server.app import default_viewer

        viewer = default_viewer()
    report = export(args.source, args.output, args.base_url, force=args.force, viewer=viewer)
    for name, manifest in report.manifests.items():
        print(f"  {name}: {manifest}")
        if report.viewer:
            print(f"    viewer: {report.viewer}?manifest={manifest}")
    print(f"wrote {args.output} ({len(report.manifests)} dataset(s), {report.rewritten} JSON "
          f"document(s) rewritten, {report.linked} file(s) hard-linked, {report.copied} copied); "
          f"publish it at {report.base_url}/")
    return 0
