"""What a portal shows of a dataset: thumbnail, metadata, rights, attribution, provider, links.

docs/dataset-format.md, "Manifest metadata". ``lanterna.json`` keeps what the publisher gave in
its ``publication`` object (from ``lanterna import``/``fit`` options or a description file), in
this form (every key optional)::

    {"rights": "http://creativecommons.org/licenses/by/4.0/",
     "attribution": "Photographs: Example Museum",
     "provider": {"label": "Example Museum", "homepage": "https://museum.example/",
                  "logo": "https://museum.example/logo.png"},
     "homepage": "https://museum.example/objects/42",
     "seeAlso": ["https://museum.example/objects/42.json"],
     "metadata": [{"label": "Object", "value": "Tablet"}]}

so every rebuild of the manifest (annotations, presets, export) writes the same properties.
:func:`publication_properties` turns it, and the dataset, into the manifest's ``thumbnail``
(always), ``metadata``, ``rights``, ``requiredStatement``, ``provider``, ``homepage`` and
``seeAlso``. :func:`check_publication` checks a ``publication`` object field by field (one-line
errors naming the field); the ``parse_*`` functions read the command-line forms. Pure: no I/O.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import PurePosixPath
from typing import Any
from urllib.parse import urlsplit

from lanterna.errors import LanternaInputError

from .services import MEDIA_TYPES, image_service

#: The keys of a ``publication`` object.
PUBLICATION_KEYS = ("rights", "attribution", "provider", "homepage", "seeAlso", "metadata")
#: The rights URIs Presentation 3 accepts (§3.3 ``rights``): a Creative Commons licence or
#: public-domain tool, or a RightsStatements.org statement, each as its own ``http`` URI with
#: the trailing slash. The description schema's ``rights`` pattern is the same (a test checks).
RIGHTS_PATTERN = (r"^(http://creativecommons\.org/(licenses/(by|by-sa|by-nd|by-nc|by-nc-sa|"
                  r"by-nc-nd)/(1\.0|2\.0|2\.1|2\.5|3\.0|4\.0)/([a-z]{2}/)?|publicdomain/"
                  r"(zero|mark)/1\.0/)|http://rightsstatements\.org/vocab/(InC|InC-OW-EU|"
                  r"InC-EDU|InC-NC|InC-RUU|NoC-CR|NoC-NC|NoC-OKLR|NoC-US|CNE|UND|NKC)/1\.0/)$")
#: An absolute http(s) URL without spaces (the description schema's ``url``).
URL_PATTERN = r"^https?://[^\s/?#]+[^\s]*$"
#: The thumbnail is the largest listed size of the first layer's image within this many pixels.
THUMBNAIL_SIDE = 400
#: Most texts (attribution, provider name, metadata labels and values), in characters.
MAX_TEXT = 1000
_MEDIA = {".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".png": "image/png", ".webp": "image/webp",
          ".svg": "image/svg+xml", ".gif": "image/gif", ".json": "application/json",
          ".jsonld": "application/ld+json", ".xml": "text/xml", ".html": "text/html",
          ".htm": "text/html", ".pdf": "application/pdf", ".txt": "text/plain"}


def check_rights(value: object) -> str:
    """Return ``value`` if it is a rights URI Presentation 3 accepts; else ``ValueError``."""
    text = str(value)
    if isinstance(value, str) and re.match(RIGHTS_PATTERN, text):
        return text
    hint = ""
    near = re.sub(r"^https://", "http://", text.strip())
    near = near if near.endswith("/") else f"{near}/"
    if re.match(RIGHTS_PATTERN, near):
        hint = f" (did you mean {near}?)"
    raise ValueError(f"not a Creative Commons or RightsStatements.org URI as Presentation 3 wants "
                     f"them{hint}, e.g. http://creativecommons.org/licenses/by/4.0/: {text!r}")


def check_url(value: object) -> str:
    """Return ``value`` if it is an absolute http(s) URL; else ``ValueError``."""
    if isinstance(value, str) and re.match(URL_PATTERN, value):
        return value
    raise ValueError(f"not an http(s) URL: {value!r}")


def check_text(value: object) -> str:
    """Return ``value`` if it is a non-empty text of at most :data:`MAX_TEXT` characters."""
    if isinstance(value, str) and value.strip() and len(value) <= MAX_TEXT:
        return value
    raise ValueError(f"not a text of 1 to {MAX_TEXT} characters: {value!r}")


def parse_provider(text: str) -> dict[str, str]:
    """``NAME[,URL[,LOGO_URL]]`` (``--provider``) as ``{label, homepage, logo}``.

    The trailing comma-separated parts that start with ``http`` are the URLs, so a name may
    hold commas (``Museum, Oxford,https://…``).
    """
    parts = text.split(",")
    urls: list[str] = []
    while len(parts) > 1 and parts[-1].strip().lower().startswith("http") and len(urls) < 2:
        urls.insert(0, parts.pop().strip())
    name = ",".join(parts).strip()
    if re.match(URL_PATTERN, name):
        raise ValueError(f"wants NAME[,URL[,LOGO_URL]] with the name first, got {text!r}")
    provider = {"label": check_text(name)}
    for key, url in zip(("homepage", "logo"), urls, strict=False):
        provider[key] = check_url(url)
    return provider


def parse_metadata(text: str) -> dict[str, str]:
    """``LABEL=VALUE`` (``--metadata``) as ``{label, value}``."""
    label, sep, value = text.partition("=")
    if not sep or not label.strip() or not value.strip():
        raise ValueError(f"wants LABEL=VALUE, got {text!r}")
    return {"label": check_text(label.strip()), "value": check_text(value.strip())}


def check_publication(pub: object, where: str = "publication") -> dict[str, Any]:
    """Return a copy of a ``publication`` object with every field checked.

    A bad field is a one-line :class:`LanternaInputError` naming it (``publication.rights: …``);
    empty fields are dropped.
    """
    if pub is None:
        return {}
    if not isinstance(pub, Mapping):
        raise LanternaInputError(None, f"{where}: not an object")
    out: dict[str, Any] = {}
    for key, value in pub.items():
        if key not in PUBLICATION_KEYS:
            raise LanternaInputError(None, f"{where}.{key}: unknown field (known: "
                                     f"{', '.join(PUBLICATION_KEYS)})")
        if value in (None, "", [], {}):
            continue
        try:
            out[key] = _CHECKS[key](value)
        except (ValueError, TypeError) as err:
            raise LanternaInputError(None, f"{where}.{key}: {err}") from None
    return out


def _check_provider(value: object) -> dict[str, str]:
    if not isinstance(value, Mapping) or set(value) - {"label", "homepage", "logo"}:
        raise ValueError("wants {label, homepage?, logo?}")
    out = {"label": check_text(value.get("label"))}
    out.update({k: check_url(value[k]) for k in ("homepage", "logo") if value.get(k)})
    return out


def _check_list(check: Any) -> Any:
    def each(value: object) -> list[Any]:
        if not isinstance(value, list):
            raise ValueError(f"not a list: {value!r}")
        return [check(v) for v in value]
    return each


def _check_pair(value: object) -> dict[str, str]:
    if not isinstance(value, Mapping) or set(value) != {"label", "value"}:
        raise ValueError(f"wants {{label, value}}, got {value!r}")
    return {"label": check_text(value["label"]), "value": check_text(value["value"])}


_CHECKS: dict[str, Any] = {"rights": check_rights, "attribution": check_text,
                           "provider": _check_provider, "homepage": check_url,
                           "seeAlso": _check_list(check_url), "metadata": _check_list(_check_pair)}


def _lang(text: str) -> dict[str, list[str]]:
    return {"en": [text]}


def _media_type(url: str) -> str | None:
    return _MEDIA.get(PurePosixPath(urlsplit(url).path).suffix.lower())


def thumbnail(desc: Mapping[str, Any], infos: Mapping[str, dict[str, Any]],
              ds_url: str) -> dict[str, Any]:
    """The manifest's thumbnail: a whole-image size of the first layer's image, with its service.

    The largest ``sizes`` entry of its ``info.json`` within :data:`THUMBNAIL_SIDE` pixels (the
    smallest when none is), a file the pyramid already holds (``full/W,H/0/default.EXT``); the
    image's ``full/max`` JPEG when its description is unknown.
    """
    image_id = str(desc["layers"][0]["body"])
    image, info = desc["images"][image_id], infos.get(image_id)
    service_id = f"{ds_url}/iiif/{image_id}"
    sizes = [(int(s["width"]), int(s["height"])) for s in (info or {}).get("sizes", [])]
    fitting = [s for s in sizes if max(s) <= THUMBNAIL_SIDE]
    if fitting or sizes:
        w, h = max(fitting) if fitting else min(sizes)
        ext = str(image.get("format", "jpg"))
        url = f"{service_id}/full/{w},{h}/0/default.{ext}"
    else:
        w, h = image.get("maxWidth", image["width"]), image.get("maxHeight", image["height"])
        ext, url = "jpg", f"{service_id}/full/max/0/default.jpg"
    return {"id": url, "type": "Image", "format": MEDIA_TYPES.get(ext, MEDIA_TYPES["jpg"]),
            "width": w, "height": h, "service": [image_service(service_id, info)]}


def publication_properties(desc: Mapping[str, Any], infos: Mapping[str, dict[str, Any]],
                           ds_url: str) -> dict[str, Any]:
    """The manifest's descriptive properties of dataset description ``desc``, in spec order.

    ``thumbnail`` always; ``metadata`` when there are wavelengths (spectral band layers) or
    given pairs; ``rights``, ``requiredStatement`` (label "Attribution"), ``provider`` (one
    ``Agent``), ``homepage`` and ``seeAlso`` when given.
    """
    pub = check_publication(desc.get("publication"), "lanterna.json: publication")
    out: dict[str, Any] = {}
    bands = [layer["service"]["wavelength"] for layer in desc["layers"]
             if "wavelength" in layer["service"]]  # spectral band layers (docs/importing.md)
    metadata = ([{"label": _lang("Wavelengths"),
                  "value": _lang(", ".join(f"{nm:g} nm" for nm in bands))}] if bands else [])
    metadata += [{"label": _lang(p["label"]), "value": _lang(p["value"])}
                 for p in pub.get("metadata", [])]
    if metadata:
        out["metadata"] = metadata
    if "attribution" in pub:
        out["requiredStatement"] = {"label": _lang("Attribution"),
                                    "value": _lang(pub["attribution"])}
    if "rights" in pub:
        out["rights"] = pub["rights"]
    if "provider" in pub:
        out["provider"] = [_agent(pub["provider"], ds_url)]
    out["thumbnail"] = [thumbnail(desc, infos, ds_url)]
    if "homepage" in pub:
        out["homepage"] = [_homepage(pub["homepage"], str(desc["label"]))]
    if "seeAlso" in pub:
        out["seeAlso"] = [_see_also(url) for url in pub["seeAlso"]]
    return out


def _homepage(url: str, label: str) -> dict[str, Any]:
    return {"id": url, "type": "Text", "label": _lang(label), "format": "text/html"}


def _agent(provider: Mapping[str, str], ds_url: str) -> dict[str, Any]:
    agent: dict[str, Any] = {"id": f"{ds_url}/manifest.json#provider", "type": "Agent",
                             "label": _lang(provider["label"])}
    if "homepage" in provider:
        agent["homepage"] = [_homepage(provider["homepage"], provider["label"])]
    if "logo" in provider:
        logo: dict[str, Any] = {"id": provider["logo"], "type": "Image"}
        media = _media_type(provider["logo"])
        if media is not None:
            logo["format"] = media
        agent["logo"] = [logo]
    return agent


def _see_also(url: str) -> dict[str, Any]:
    media = _media_type(url)
    ref: dict[str, Any] = {"id": url, "type": "Text" if media == "text/html" else "Dataset"}
    if media is not None:
        ref["format"] = media
    return ref
