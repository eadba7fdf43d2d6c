"""The recorder's writer process on its own: what it says when the file cannot be written."""
import os
from pathlib import Path
import pickle
import subprocess
import sys

from cam_ros.recording.mcap_file import FileSpec
from cam_ros.recording.writer_process import STARTER

REPO = Path(__file__).resolve().parents[2]
SPEC = FileSpec(name='broken.mcap', topics=(), channel_qos=(), schemas={}, compression='none',
                chunk_size=1024, attachments={}, description={}, opened_ns=0)


def test_a_refused_write_is_said_once_and_closing_adds_no_traceback():
    """
    Every write to the file fails (a pipe without a reader: EPIPE, as a full disk fails).

    The writer answers the failure and exits 1; closing the file, whose buffered bytes fail
    again, must add nothing: the node already has the error.
    """
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        writer = subprocess.run(
            [sys.executable, '-c', STARTER, str(write_end)], input=pickle.dumps(('open', SPEC)),
            capture_output=True, pass_fds=(write_end,), timeout=60,
            env=dict(os.environ, PYTHONPATH=str(REPO)))
    finally:
        os.close(write_end)
    assert pickle.loads(writer.stdout) == ('error', 'Broken pipe')
    assert (writer.returncode, writer.stderr.decode()) == (1, '')
