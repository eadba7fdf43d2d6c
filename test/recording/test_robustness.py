"""A recorder killed with SIGKILL or stopped by a write error leaves a readable file."""

import json
from pathlib import Path

from cam_ros.recording import open_recording

from .recording_support import (CHILD_TIMEOUT, CHUNK_SIZE, KILL_AFTER, record_then_kill,
                                start_child)

#: Bytes of one recorded message record besides its data (opcode, length, channel id,
#: sequence, log and publish time), per the MCAP specification.
MESSAGE_RECORD_OVERHEAD = 1 + 8 + 2 + 4 + 8 + 8
#: Bytes the file may still grow once the file-size limit is set.
FSIZE_HEADROOM = 3000


def positions(path: Path) -> list[float]:
    """Return position[0] of every message in a (possibly unfinished) recording."""
    return [m.message.position[0] for m in open_recording(path).messages()]


def test_sigkill_loses_at_most_the_open_chunk(python, child_env, tmp_path):
    path = tmp_path / 'killed.mcap'
    written = record_then_kill(python, child_env, path)
    assert written >= KILL_AFTER
    recording = open_recording(path)
    assert not recording.complete
    recovered = positions(path)
    assert recovered == [float(i) for i in range(len(recovered))]
    [data] = {len(m.message) for m in recording.messages(raw=True)}
    per_chunk = CHUNK_SIZE // (data + MESSAGE_RECORD_OVERHEAD) + 1
    assert len(recovered) >= written - per_chunk


def test_write_error_stops_recording_but_not_the_process(python, child_env, tmp_path):
    path = tmp_path / 'limited.mcap'
    child = start_child(python, child_env, path, CHUNK_SIZE, FSIZE_HEADROOM)
    try:
        out, err = child.communicate(timeout=CHILD_TIMEOUT)
    finally:
        child.kill()
    assert child.returncode == 0, err
    status = json.loads(out.splitlines()[-1])
    assert status['alive'] and status['subscriptions'] == 0
    assert 'File too large' in status['error'] and str(path) in status['error']
    assert 'File too large' in err and '[ERROR]' in err
    recovered = positions(path)
    assert 0 < len(recovered) <= status['written'] < status['published']
    assert recovered == [float(i) for i in range(len(recovered))]
    assert path.stat().st_size <= status['limit']
