"""A sweep's folder: one sub-folder a variant (its scene, report.json,
final mesh and result.json) and ``manifest.json`` listing them all.

A variant is done when its ``result.json`` is there and was made from the
same scene, frames and backend; a sweep run again after an interruption
reruns only the variants that are not done. Files are written to a
temporary name and renamed, so an interruption never leaves half a file.
"""

from __future__ import annotations

import hashlib
import json
import os
from typing import Any, Dict, List, Optional

MANIFEST = "manifest.json"
RESULT = "result.json"


def key(job: Dict[str, Any]) -> str:
    """A digest of what decides a variant's figures (its scene text, frames
    and backend; threads do not change them)."""
    what = json.dumps([job["scene_json"], job["frames"], job["backend"], job["mesh"]])
    return hashlib.sha256(what.encode()).hexdigest()[:16]


def folder_name(index: int) -> str:
    """The sub-folder of variant ``index``."""
    return f"variant_{index:04d}"


class Store:
    """The folder ``out`` of one sweep."""

    def __init__(self, out: "os.PathLike[str] | str"):
        self.out = os.fspath(out)
        os.makedirs(self.out, exist_ok=True)

    def done(self, index: int, job_key: str) -> Optional[Dict[str, Any]]:
        """The row of variant ``index`` if a run of the same variant
        finished before, else None."""
        path = os.path.join(self.out, folder_name(index), RESULT)
        try:
            with open(path, encoding="utf-8") as f:
                result = json.load(f)
        except (OSError, ValueError):
            return None
        return result["row"] if result.get("key") == job_key else None

    def save(self, index: int, job_key: str, row: Dict[str, Any], files: Dict[str, bytes]) -> None:
        """Writes variant ``index``'s files, then its result (last: it marks
        the variant done)."""
        folder = os.path.join(self.out, folder_name(index))
        os.makedirs(folder, exist_ok=True)
        for name, data in files.items():
            _write(os.path.join(folder, name), data)
        result = {"key": job_key, "row": row}
        _write(os.path.join(folder, RESULT), _json(result))

    def manifest(self, header: Dict[str, Any], rows: List[Optional[Dict[str, Any]]]) -> None:
        """Writes manifest.json: the sweep (``header``) and every variant,
        done (its row) or still to run."""
        variants = [
            {"variant": i, "folder": folder_name(i), "done": row is not None, "row": row}
            for i, row in enumerate(rows)
        ]
        done = sum(1 for r in rows if r is not None)
        body = dict(header, total=len(rows), done=done, variants=variants)
        _write(os.path.join(self.out, MANIFEST), _json(body))


def _json(value: Any) -> bytes:
    return (json.dumps(value, indent=2) + "\n").encode()


def _write(path: str, data: bytes) -> None:
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)
