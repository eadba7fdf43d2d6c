"""The studio's web app (Starlette): the page, its assets and the JSON API over one design file.

Routes: GET / (the page), GET /assets/NAME (its script, style sheet and plotly.js, all served
here: nothing from the internet), GET /api/design (the file's values as texts), POST
/api/view (what the page draws for edited values, or the one-line error at its field), POST
/api/position (a motion's position at a cam angle, for splitting a segment), POST /api/axes
(a machine's values with an axis added or removed, as the core judges them), POST /api/report,
POST /api/save, POST /api/export (a download made by the CLI's command); with a live node
(live.py): GET /api/live (what the node does), POST /api/live/engage, POST /api/live/apply.

Security: the app reads and writes nothing but its design file (and a scratch folder inside
the design's folder for downloads); no request names a path. On 127.0.0.1 it answers only
requests whose Host is the loopback's (no DNS rebinding); on another host every request needs
the token (in the URL once, then a cookie), as Jupyter does. A POST must carry JSON, which a
page from elsewhere cannot send without the browser asking first (CORS), so no other site can
make the studio save, export, apply to a node or engage it.
"""
from __future__ import annotations

import math
import re
import secrets
from functools import lru_cache
from pathlib import Path
from typing import Any, Awaitable, Callable, TYPE_CHECKING

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import JSONResponse, PlainTextResponse, Response
from starlette.routing import Route
from starlette.types import ASGIApp, Receive, Scope, Send

from cam_ros.core import CamError, InvalidParameter, LAWS, PARAMETERS
from cam_ros.core.errors import one_line
from cam_ros.core.machine import is_machine
from cam_ros.core.machine.served import machine_from_values
from cam_ros.studio import exports
from cam_ros.studio.axes import with_axis, without_axis
from cam_ros.studio.document import DesignDocument, typed_values, value_text
from cam_ros.studio.view import design_view, json_ready

if TYPE_CHECKING:  # only a studio started with --node imports rclpy
    from cam_ros.studio.live import LiveLink

STATIC = Path(__file__).resolve().parent / 'static'
#: The page's own files, by the name the page asks for, and their media types.
ASSETS = {'studio.js': 'text/javascript', 'axes.js': 'text/javascript',
          'live.js': 'text/javascript', 'studio.css': 'text/css',
          'plotly.min.js': 'text/javascript'}
LOOPBACK_HOSTS = ('127.0.0.1', 'localhost', '::1')
TOKEN_COOKIE = 'cam_ros_studio_token'
#: The field an error names: a parameter's name with its index (`jaw.motion.end_deg[1]`).
ERROR_KEY = re.compile(r'[A-Za-z_][\w.]*(\[\d+\])?')

#: Each parameter's help for the page: its description and unit.
PARAMETER_HELP = {spec.name: f'{spec.description}' + (f' ({spec.unit})' if spec.unit else '')
                  for spec in PARAMETERS}


@lru_cache(maxsize=None)
def asset(name: str) -> bytes:
    """Return one of the page's files; plotly.js from the installed plotly package."""
    if name == 'plotly.min.js':
        from plotly.offline import get_plotlyjs

        return get_plotlyjs().encode('utf-8')
    return (STATIC / name).read_bytes()


def error_data(err: CamError) -> dict[str, Any]:
    """Return an error for the page: its text as the CLI prints it, and the field it names."""
    parameter = getattr(err, 'parameter', '')
    match = ERROR_KEY.match(parameter)
    return {'error': {'key': match.group(0) if match else '', 'text': one_line(str(err))}}


class Guard:
    """Let a request through only from the loopback (local mode) or with the token."""

    def __init__(self, app: ASGIApp, token: str | None):
        self.app = app
        self.token = token

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope['type'] != 'http':
            await self.app(scope, receive, send)
            return
        request = Request(scope)
        refusal = self.refusal(request)
        if refusal is not None:
            await PlainTextResponse(refusal, status_code=403)(scope, receive, send)
            return
        await self.app(scope, receive, send)

    def refusal(self, request: Request) -> str | None:
        """Return why a request is refused, None to let it through."""
        if self.token is None:
            host = request.url.hostname or ''  # from the Host header, IPv6 unbracketed
            if host not in LOOPBACK_HOSTS:
                return f'cam_ros studio: host {host!r} refused: this studio serves 127.0.0.1 only'
        else:
            given = (request.query_params.get('token') or request.cookies.get(TOKEN_COOKIE)
                     or request.headers.get('x-studio-token') or '')
            if not secrets.compare_digest(given.encode(), self.token.encode()):
                return 'cam_ros studio: a token is needed: open the URL cam_ros studio printed'
        if request.method == 'POST' and request.headers.get('content-type', '').split(';')[0] \
                != 'application/json':
            return 'cam_ros studio: a POST must carry application/json'
        return None


def create_app(document: DesignDocument, token: str | None = None,
               live: LiveLink | None = None) -> ASGIApp:
    """Return the studio's app over one design file; token: needed by every request; live:
    the running node the page shows and drives (None: no node)."""

    async def page(request: Request) -> Response:
        response = Response((STATIC / 'index.html').read_bytes(), media_type='text/html')
        if token is not None and request.query_params.get('token'):
            response.set_cookie(TOKEN_COOKIE, token, httponly=True, samesite='strict')
        return response

    async def static(request: Request) -> Response:
        name = request.path_params['name']
        if name == 'favicon.ico':
            return Response(status_code=204)
        if name not in ASSETS:
            return PlainTextResponse('not found', status_code=404)
        return Response(asset(name), media_type=ASSETS[name],
                        headers={'Cache-Control': 'no-cache'})

    async def design(request: Request) -> Response:
        values = document.values
        return JSONResponse({'label': document.label, 'name': document.path.name,
                             'read_only': document.read_only, 'machine': is_machine(values),
                             'values': {key: value_text(value) for key, value in values.items()},
                             'laws': list(LAWS), 'parameters': PARAMETER_HELP,
                             'live': None if live is None else live.name})

    def handler(work: Callable[[dict[str, Any]], Any]) -> Callable[[Request], Awaitable[Response]]:
        """Return a POST endpoint running work(body) in a thread; a CamError is its one line."""
        async def endpoint(request: Request) -> Response:
            body = await request.json()
            if not isinstance(body, dict):
                return JSONResponse({'error': {'key': '', 'text': 'a JSON object is needed'}},
                                    status_code=400)
            try:
                result = await run_in_threadpool(work, body)
            except CamError as err:
                return JSONResponse(error_data(err), status_code=422)
            return result if isinstance(result, Response) else JSONResponse(result)
        return endpoint

    def values_of(body: dict[str, Any]) -> dict[str, Any]:
        texts = body.get('values')
        if not isinstance(texts, dict):
            raise InvalidParameter('values', type(texts).__name__, 'must be an object of '
                                   'parameter texts')
        return typed_values(texts)

    def view(body: dict[str, Any]) -> Any:
        return design_view(values_of(body), body.get('axis'))

    def position(body: dict[str, Any]) -> Any:
        machine = machine_from_values(values_of(body))
        names = machine.config.names
        axis = machine.axes[names.index(body['axis']) if body.get('axis') in names else 0]
        unit, factor = axis.design.config.file_position_unit
        angle = float(body.get('deg', 0.0))
        state = axis.design.evaluate([math.radians(angle)])
        return {'position': float(state.position[0]) * factor, 'unit': unit}

    def axes(body: dict[str, Any]) -> Any:
        values = values_of(body)
        name, source = body.get('add'), body.get('copy_of')
        if isinstance(name, str) and isinstance(source, str):
            changed = with_axis(values, name, source)
        elif isinstance(body.get('remove'), str):
            changed = without_axis(values, body['remove'])
        else:
            raise InvalidParameter('axes', None, 'an axis edit needs add and copy_of, or remove')
        machine_from_values(changed)  # judged by the core, as every edit
        if isinstance(name, str):
            document.copies[name] = str(source)  # its file section: a copy of the source's
        return {'values': {key: value_text(value) for key, value in changed.items()}}

    def report(body: dict[str, Any]) -> Any:
        return {'text': exports.report(document, values_of(body), bool(body.get('json')))}

    def save(body: dict[str, Any]) -> Any:
        values = values_of(body)
        machine_from_values(values)  # a design the core refuses is never saved
        document.save(values)
        return {'saved': document.label,
                'report': exports.report(document, document.values, False)}

    def export(body: dict[str, Any]) -> Any:
        options = body.get('options') or {}
        if not isinstance(options, dict):
            raise InvalidParameter('options', options, 'must be an object')
        made = exports.download(document, values_of(body), str(body.get('kind')), options,
                                body.get('axis'))
        return Response(made.data, media_type='application/octet-stream', headers={
            'Content-Disposition': f'attachment; filename="{made.name}"',
            'X-Cam-Ros-Message': made.message.encode('ascii', 'replace').decode()
            .replace('\n', ' | ')})

    def linked() -> LiveLink:
        if live is None:
            raise InvalidParameter('--node', None, 'is needed to drive a running node: start '
                                   '`cam_ros studio FILE --node /cam`')
        return live

    async def live_status(request: Request) -> Response:
        if live is None:
            return JSONResponse({'node': None})
        return JSONResponse(json_ready(await run_in_threadpool(live.status)))

    def engage(body: dict[str, Any]) -> Any:
        return linked().engage(body.get('engage') is True)

    def apply(body: dict[str, Any]) -> Any:
        return linked().apply(values_of(body))

    routes = [Route('/', page), Route('/assets/{name}', static),
              Route('/{name:str}', static),
              Route('/api/design', design),
              Route('/api/view', handler(view), methods=['POST']),
              Route('/api/position', handler(position), methods=['POST']),
              Route('/api/axes', handler(axes), methods=['POST']),
              Route('/api/report', handler(report), methods=['POST']),
              Route('/api/save', handler(save), methods=['POST']),
              Route('/api/export', handler(export), methods=['POST']),
              Route('/api/live', live_status),
              Route('/api/live/engage', handler(engage), methods=['POST']),
              Route('/api/live/apply', handler(apply), methods=['POST'])]
    return Guard(Starlette(routes=routes), token)
