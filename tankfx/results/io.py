"""Writing results: JSON with the numbers as Python writes them, never NaN."""
from __future__ import annotations

import json
import os
from pathlib import Path


def write_json(path: Path, data: dict) -> None:
    """Write a results dict as JSON, atomically: a reader never sees a half-written file.

    Parameters
    ----------
    path : pathlib.Path
        The file to write.
    data : dict
        JSON-serialisable data; NaN and infinity are refused.
    """
    tmp = path.with_suffix(path.suffix + ".tmp")
    with tmp.open("w") as f:
        json.dump(data, f, indent=1, allow_nan=False)
        f.write("\n")
    os.replace(tmp, path)
