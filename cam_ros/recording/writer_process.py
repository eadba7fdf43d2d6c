"""
The recorder's writer process: MCAP serialisation, compression and file writes, off the node.

The node's process keeps only the taking of messages (in-process delivery is the cheapest for
publish(); another process's reader costs it more: docs/recording.md) and sends each batch down a
pipe; this process writes them. Commands are pickled tuples on stdin: ('open', FileSpec) first,
then ('write', index, records), ('flush',) and ('close',); the answers on stdout are ('closed',
counts) or ('error', text), after which it exits. End of input without 'close' means the node
died: it exits at once without a summary, as a killed recorder would.
It runs STARTER with the new file's descriptor (opened by the node) as argument.
"""

import contextlib
import os
from pathlib import Path
import pickle
import signal
import subprocess
import sys
import threading
from typing import Any, BinaryIO, Optional, Sequence

from cam_ros.recording.mcap_file import FileSpec, McapFile, Record

#: The writer's command line (python -c): it imports this module without the package's
#: __init__, which loads rclpy (slow, and this process needs only mcap and yaml).
STARTER = f'''
import sys, types
package = types.ModuleType('cam_ros.recording')
package.__path__ = [{str(Path(__file__).parent)!r}]
sys.modules['cam_ros.recording'] = package
from cam_ros.recording.writer_process import main
sys.exit(main())
'''
#: Seconds to wait for the writer to finish the file on close (summary of a large recording).
CLOSE_TIMEOUT_S = 60.0


class WriterGone(Exception):
    """The writer process stopped: `text` says why (a write error, or that it died)."""

    def __init__(self, text: str):
        super().__init__(text)
        self.text = text


class WriterProcess:
    """The node's side: start the writer on an open file, send it batches, close it."""

    def __init__(self, file: BinaryIO, spec: FileSpec):
        """Start the writer process on `file` (it gets its own copy of the descriptor)."""
        package_root = str(Path(__file__).resolve().parents[2])
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            filter(None, [package_root, os.environ.get('PYTHONPATH')])))
        fd = file.fileno()
        self._process = subprocess.Popen(
            [sys.executable, '-c', STARTER, str(fd)], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, pass_fds=(fd,), env=env, start_new_session=True)
        self._lock = threading.Lock()
        self._send(('open', spec))
        kind, value = self._answer()
        if kind != 'opened':
            self.kill()
            raise WriterGone(value)

    @property
    def pid(self) -> int:
        """Return the writer's process id."""
        return self._process.pid

    def write(self, index: int, records: Sequence[Record]) -> None:
        """Send messages of topic `index` to be written (WriterGone if the writer stopped)."""
        self._send(('write', index, records))

    def check(self) -> None:
        """Raise WriterGone if the writer has stopped."""
        if self._process.poll() is not None:
            raise WriterGone(self._outcome()[1])

    def flush(self) -> None:
        """Have the writer write out its open chunk; raise WriterGone if it has stopped."""
        self.check()
        self._send(('flush',))

    def close(self) -> list[int]:
        """Have the writer finish the file; return its counts (WriterGone if it could not)."""
        self._send(('close',))
        kind, value = self._outcome()
        if kind != 'closed':
            raise WriterGone(value)
        return value

    def kill(self) -> None:
        """End the writer without finishing the file (after an error)."""
        if self._process.poll() is None:
            self._process.kill()
        self._outcome()

    def _send(self, command: tuple[Any, ...]) -> None:
        stdin = self._process.stdin
        assert stdin is not None
        with self._lock:
            try:
                pickle.dump(command, stdin, pickle.HIGHEST_PROTOCOL)
                stdin.flush()
            except (BrokenPipeError, ValueError):
                raise WriterGone(self._outcome()[1]) from None

    def _answer(self) -> tuple[str, Any]:
        """Return the writer's next answer (('error', text) when it ended without one)."""
        stdout = self._process.stdout
        assert stdout is not None
        try:
            if not stdout.closed:
                return pickle.load(stdout)
        except (EOFError, pickle.UnpicklingError, OSError):
            pass
        return ('error', 'the writer process ended')

    def _outcome(self) -> tuple[str, Any]:
        """Wait for the writer to end; return its last answer ('error', text when none)."""
        stdout = self._process.stdout
        assert stdout is not None
        answer = self._answer()
        try:
            code = self._process.wait(CLOSE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._process.kill()
            code = self._process.wait()
        for pipe in (self._process.stdin, stdout):
            try:
                pipe.close()
            except OSError:
                pass
        if answer == ('error', 'the writer process ended') and code:
            answer = ('error', f'the writer process ended with exit code {code}')
        return answer


def serve(file: BinaryIO, commands: BinaryIO, answers: BinaryIO) -> int:
    """Write what the commands say until 'close' (0) or end of input or an error (1)."""
    recording: Optional[McapFile] = None
    try:
        while True:
            try:
                command = pickle.load(commands)
            except EOFError:
                return 1  # the node died: leave the file as a killed recorder would
            kind = command[0]
            if kind == 'open':
                recording = McapFile(file, command[1])
                _say(answers, ('opened', None))
            elif recording is None:
                raise RuntimeError(f'{kind!r} before open')
            elif kind == 'write':
                recording.write(command[1], command[2])
            elif kind == 'flush':
                recording.flush()
            elif kind == 'close':
                recording.finish()
                file.close()
                _say(answers, ('closed', recording.counts))
                return 0
    except OSError as exc:
        _say(answers, ('error', exc.strerror or str(exc)))
        return 1


def _say(answers: BinaryIO, answer: tuple[Any, ...]) -> None:
    pickle.dump(answer, answers)
    answers.flush()


def main() -> int:
    """Serve the node on stdin/stdout, writing to the file descriptor given as argument."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the node closes it; Ctrl-C is for the node
    file = os.fdopen(int(sys.argv[1]), 'wb')
    try:
        return serve(file, sys.stdin.buffer, sys.stdout.buffer)
    finally:
        with contextlib.suppress(OSError):  # serve told the node of a failed write; the
            file.close()  # buffered rest fails again on close


if __name__ == '__main__':
    sys.exit(main())
