"""Serve the studio: bind, say where, run uvicorn until Ctrl-C (with --node: linked to it)."""
from __future__ import annotations

import secrets
import socket
import sys
import threading
import webbrowser
from pathlib import Path
from typing import TYPE_CHECKING

import uvicorn

from cam_ros.studio.app import create_app
from cam_ros.studio.document import DesignDocument

if TYPE_CHECKING:
    from cam_ros.studio.live import LiveLink

LOCAL_HOST = '127.0.0.1'


def studio_url(host: str, port: int, token: str | None) -> str:
    """Return the URL a browser opens: with the token when one is needed."""
    shown = f'[{host}]' if ':' in host else host
    return f'http://{shown}:{port}/' + ('' if token is None else f'?token={token}')


def bind(host: str, port: int) -> socket.socket:
    """Return a listening socket on host:port (port 0: a free one)."""
    family = socket.AF_INET6 if ':' in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind((host, port))
    sock.listen(128)
    return sock


def make_server(document: DesignDocument, token: str | None,
                live: LiveLink | None = None) -> uvicorn.Server:
    """Return the uvicorn server of the studio app (not started: run it on a bound socket)."""
    config = uvicorn.Config(create_app(document, token, live), log_level='warning',
                            lifespan='off')
    return uvicorn.Server(config)


def serve(document: DesignDocument, host: str, port: int, open_browser: bool,
          node: str | None = None) -> None:
    """Run the studio on host:port until interrupted; print its URL (stderr: a warning).

    node: a running cam_node the page shows and drives (live.py), None: none.
    """
    token = None if host == LOCAL_HOST else secrets.token_urlsafe(24)
    sock = bind(host, port)
    url = studio_url(host, sock.getsockname()[1], token)
    if token is not None:
        print(f'cam_ros studio: warning: serving on {host}, not only on this computer: '
              f'anyone who can reach it and has the URL with its token can edit and save '
              f'{document.path}', file=sys.stderr, flush=True)
    live = None
    if node is not None:
        from cam_ros.studio.live import LiveLink

        live = LiveLink(node, document.values)
    linked = '' if live is None else f', linked to {live.name}'
    print(f'cam_ros studio: serving {document.label}{linked} at {url} (Ctrl-C stops)',
          flush=True)
    server = make_server(document, token, live)
    if open_browser:
        threading.Timer(0.5, webbrowser.open, (url,)).start()
    try:
        server.run(sockets=[sock])
    finally:
        if live is not None:
            live.close()


def run_in_thread(document: DesignDocument, host: str = LOCAL_HOST, token: str | None = None,
                  live: LiveLink | None = None) -> tuple[uvicorn.Server, threading.Thread, str]:
    """Start the studio in a thread on a free port (tests, benchmarks); return its URL too."""
    sock = bind(host, 0)
    server = make_server(document, token, live)
    thread = threading.Thread(target=server.run, kwargs={'sockets': [sock]}, daemon=True)
    thread.start()
    return server, thread, studio_url(host, sock.getsockname()[1], token)


def document_of(config: str | None) -> DesignDocument:
    """Return the design a studio opens: FILE, or the shipped default design, read-only."""
    if config is None:
        from cam_ros.paths import default_config_path

        return DesignDocument(default_config_path(), read_only=True)
    return DesignDocument(Path(config))
