"""What the studio's tests share: the running studio, its API, and the CLI to compare with."""
from __future__ import annotations

import json
import subprocess
import sys
import urllib.error
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
CONFIG_DIR = REPO / 'config'
CLI_TIMEOUT_S = 300


@dataclass(frozen=True)
class Answer:
    """An HTTP answer: status, headers, body."""

    status: int
    headers: dict[str, str]
    body: bytes

    def json(self) -> Any:
        return json.loads(self.body)


@dataclass(frozen=True)
class Studio:
    """A studio serving a design file: its URL and the file."""

    url: str
    path: Path

    def get(self, route: str, headers: dict[str, str] | None = None) -> Answer:
        return request(self.url + route, None, headers or {})

    def post(self, route: str, body: Any, headers: dict[str, str] | None = None) -> Answer:
        return request(self.url + route, json.dumps(body).encode(),
                       {'Content-Type': 'application/json', **(headers or {})})

    def texts(self) -> dict[str, Any]:
        """Return the design's values as the page gets them."""
        return self.get('api/design').json()['values']


def request(url: str, data: bytes | None, headers: dict[str, str]) -> Answer:
    """Make one HTTP request; an error status is an answer too."""
    try:
        with urllib.request.urlopen(urllib.request.Request(url, data, headers),
                                    timeout=CLI_TIMEOUT_S) as response:
            return Answer(response.status, dict(response.headers), response.read())
    except urllib.error.HTTPError as err:
        return Answer(err.code, dict(err.headers), err.read())


def cli(*argv: object, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """Run `cam_ros` as a user does, in its own process."""
    return subprocess.run([sys.executable, '-m', 'cam_ros.cli', *map(str, argv)],
                          capture_output=True, text=True, timeout=CLI_TIMEOUT_S, cwd=cwd)


def edited_file(source: Path, target: Path, replacements: list[tuple[str, str]]) -> Path:
    """Write source's text with each (old, new) replaced once to target: an edit by hand."""
    text = source.read_text()
    for old, new in replacements:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    target.write_text(text)
    return target
