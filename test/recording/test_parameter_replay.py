"""--apply-parameters: recorded parameter events are set once each, before the right message."""

from rcl_interfaces.msg import ParameterType

from cam_ros.cli import main
from cam_ros.recording import open_recording, ParameterChange, Player
from cam_ros.recording.parameter_replay import parameter_events, ParameterSchedule

from .recording_support import STREAM_TOPIC


def change(time_ns, name, new, node='/cam', kind='changed'):
    return ParameterChange(time_ns, node, name, kind, None, new)


def test_events_group_per_node_and_time_and_leave_out_deletions_and_recording():
    changes = [change(5, 'slave.offset', 0.001), change(5, 'master.offset_deg', 10.0),
               change(5, 'recording.enabled', True), change(5, 'lift_m', 1.0, node='/other'),
               change(9, 'switches.names', []), change(9, 'old', None, kind='deleted')]
    events = parameter_events(changes)
    assert [(e.time_ns, e.node, [c.name for c in e.changes]) for e in events] == [
        (5, '/cam', ['slave.offset', 'master.offset_deg']), (5, '/other', ['lift_m']),
        (9, '/cam', ['switches.names'])]
    (offset, degrees), (names,) = events[0].messages(), events[2].messages()
    assert (offset.value.type, offset.value.double_value) == (ParameterType.PARAMETER_DOUBLE,
                                                              0.001)
    assert degrees.value.double_value == 10.0
    # An empty list gets the schema's type, not rclpy's guess (a byte array).
    assert names.value.type == ParameterType.PARAMETER_STRING_ARRAY
    assert list(names.value.string_array_value) == []


def test_player_sets_each_event_before_the_first_message_logged_at_or_after_it(
        reference, graph_nodes):
    recording = open_recording(reference.path)
    times = [m.log_time_ns for m in recording.messages([STREAM_TOPIC], raw=True)]
    # At a message's own log time, between two messages, before the first and after the last.
    due = {times[3]: 3, (times[10] + times[11]) // 2: 11, times[0] - 1: 0, times[-1] + 1: None}
    events = parameter_events(change(at, 'slave.offset', float(k)) for k, at in
                              enumerate(sorted(due)))
    log = []
    schedule = ParameterSchedule(events, lambda event: log.append(('set', event.time_ns)))
    with Player(recording, graph_nodes('parameter_player'), topics=[STREAM_TOPIC]) as player:
        count = player.play(rate=None, before_message=schedule,
                            on_message=lambda m: log.append(('message', m.log_time_ns)))
    assert count == len(times)
    assert [at for kind, at in log if kind == 'message'] == times
    for at, index in due.items():
        if index is None:  # nothing follows it: never set
            assert ('set', at) not in log
            continue
        position = log.index(('set', at))
        following = next(entry for entry in log[position:] if entry[0] == 'message')
        assert following == ('message', times[index])
        assert sum(entry[0] == 'message' for entry in log[:position]) == index
    schedule(times[-1] + 1)  # a later time sets what is left, once
    assert log.count(('set', times[-1] + 1)) == 1


def test_apply_parameters_refuses_loop(capsys, tmp_path):
    assert main(['replay', str(tmp_path / 'none.mcap'), '--apply-parameters', '--loop']) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith('cam_ros replay: --apply-parameters = True')
    assert 'cannot go with --loop' in err[0]
