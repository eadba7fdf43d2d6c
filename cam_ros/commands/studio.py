"""`cam_ros studio`: edit a design file in the browser (see cam_ros.studio)."""
from __future__ import annotations

from cam_ros.core import InvalidParameter
from cam_ros.core.machine.served import machine_from_values
from cam_ros.exit_codes import EXIT_OK


def studio(config: str | None = None, port: int = 8770, host: str = '127.0.0.1',
           open_browser: bool = False, node: str | None = None) -> int:
    """Serve the studio for one design file until Ctrl-C; print its URL; node: a running
    cam_node to show and drive."""
    from cam_ros.studio.server import document_of, serve

    if not 0 <= port <= 65535:
        raise InvalidParameter('--port', port, 'must be in 0..65535 (0: a free port)')
    document = document_of(config)
    machine_from_values(document.values)  # a design the CLI refuses is refused as it does
    try:
        serve(document, host, port, open_browser, node)
    except OSError as err:
        raise InvalidParameter('--port', port, f'cannot be served on {host} '
                               f'({err.strerror or err})') from err
    except KeyboardInterrupt:
        pass
    return EXIT_OK
