"""Recorded ~/engage calls are due before the master message after the one they followed."""

from cam_ros_interfaces.msg import EngageRequest

from cam_ros.recording import RecordedMessage
from cam_ros.recording.engage_replay import engage_calls, engage_topics
from cam_ros.recording.replay import default_topics
from cam_ros.recording.schedule import Schedule

from .recording_support import master, stamped, state, StubRecording

STAMPS = [7 * 10 ** 9 + 4_000_000 * k for k in range(12)]  # 250 Hz, logged 10 ns apart
STREAM = [master(10 * (k + 1), stamp) for k, stamp in enumerate(STAMPS)]


def request(log_ns, engage, after=None, node='/cam', success=True):
    """Return a recorded EngageRequest answered after the master message stamped after."""
    message = EngageRequest(master_followed=after is not None, engage=engage, success=success,
                            message=f'answer {log_ns}')
    if after is not None:
        stamped(message, after)
    return RecordedMessage(f'{node}/engage_requests', message, log_ns, log_ns)


def test_each_call_is_due_before_the_next_master_message_of_its_node():
    recording = StubRecording(STREAM + [
        state(1, 0, 'none'),  # names /cam's master topic
        request(3, True),  # before any master message: before the first one
        request(45, False, after=STAMPS[3], success=False),  # after the 4th (logged 40)
        request(44, True, after=STAMPS[4]),  # logged before the 5th it followed: after it
        request(2, True, after=STAMPS[0] - 1),  # latched from before the recording
        request(130, True, after=STAMPS[11]),  # after the last: nothing follows, its own time
        request(7, False, node='/other')])  # a node without ~/state: its own time
    topics = engage_topics(recording)
    assert sorted(topics) == ['/cam/engage_requests', '/other/engage_requests']
    calls = engage_calls(recording, topics)
    assert [(c.time_ns, c.service, c.engage, c.success) for c in calls] == [
        (7, '/other/engage', False, True), (10, '/cam/engage', True, True),
        (10, '/cam/engage', True, True), (50, '/cam/engage', False, False),
        (60, '/cam/engage', True, True), (130, '/cam/engage', True, True)]
    assert calls[3].message == 'answer 45'
    assert engage_calls(recording, ['/other/engage_requests']) == calls[:1]


def test_default_topics_are_the_inputs_and_never_the_engage_calls():
    messages = STREAM + [state(1, 0, 'none'), request(3, True)]
    outputs = frozenset({'/cam/state'})
    assert default_topics(StubRecording(messages, outputs)) == ['/cam/master']
    assert default_topics(StubRecording(messages, outputs), outputs=True) == [
        '/cam/state', '/cam/master']
    # A recording that does not name its node's outputs: every topic (but the calls).
    assert default_topics(StubRecording(messages)) == ['/cam/state', '/cam/master']


def test_schedule_applies_each_item_once_and_finish_applies_the_rest():
    calls = engage_calls(StubRecording(STREAM + [
        state(1, 0, 'none'), request(3, True), request(45, False, after=STAMPS[3]),
        request(130, True, after=STAMPS[11])]), ['/cam/engage_requests'])
    applied = []
    schedule = Schedule(calls, applied.append)
    schedule(9)
    assert applied == []
    schedule(10)
    schedule(10)
    assert applied == calls[:1]
    schedule(120)  # the last master message
    assert applied == calls[:2]
    schedule.finish()
    schedule.finish()
    assert applied == calls
