"""Render a report page in headless Chromium and take a screenshot (a check that the
self-contained page really opens in a browser).

Chromium comes from Debian's packages: ``apt-get install -y chromium``.  Every run uses a new,
empty profile folder and turns off networking side-channels, so it reads nothing but the page.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from planerel.errors import DependencyError, InputError

__all__ = ["find_chromium", "screenshot"]

_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_chromium() -> str | None:
    """Path of a Chromium/Chrome executable on the PATH, or None."""
    for name in _NAMES:
        p = shutil.which(name)
        if p:
            return p
    return None


def screenshot(html_path, png_path, *, size=(1200, 3000), timeout: float = 120.0) -> Path:
    """Open ``html_path`` in headless Chromium and write a PNG screenshot of it.

    Parameters
    ----------
    html_path : str or Path
        The page (opened as a ``file://`` URL).
    png_path : str or Path
        Screenshot to write.
    size : (int, int)
        Window width and height in CSS pixels.
    timeout : float
        Seconds before Chromium is stopped.

    Returns
    -------
    Path
        ``png_path``.

    Raises
    ------
    DependencyError
        No Chromium on the PATH (the message says how to install it).
    InputError
        The page does not exist, or Chromium failed / wrote no screenshot.
    """
    import subprocess
    import tempfile

    page = Path(html_path).resolve()
    if not page.is_file():
        raise InputError(f"{page}: no such page to render")
    exe = find_chromium()
    if exe is None:
        raise DependencyError("Chromium is not installed; install it with "
                              "'apt-get install -y chromium' (Debian)")
    out = Path(png_path).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    if out.exists():
        out.unlink()
    w, h = (int(v) for v in size)
    with tempfile.TemporaryDirectory(prefix="planerel-chromium-") as profile:
        cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
               "--no-first-run", "--disable-background-networking", "--disable-component-update",
               "--disable-sync", "--hide-scrollbars", f"--user-data-dir={profile}",
               f"--screenshot={out}", f"--window-size={w},{h}", page.as_uri()]
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise InputError(f"Chromium did not finish rendering {page} within {timeout:g} s") \
                from None
    if not out.is_file() or out.stat().st_size == 0:
        tail = (r.stderr or "").strip().splitlines()[-3:]
        raise InputError(f"Chromium wrote no screenshot of {page} (exit code {r.returncode}: "
                         f"{' / '.join(tail)})")
    return out
