"""--apply-parameters: recorded parameter events are set once each, before the right message."""

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from rcl_interfaces.msg import ParameterType

from cam_ros.cli import main
from cam_ros.recording import open_recording, ParameterChange, Player, RecordedMessage
from cam_ros.recording.parameter_replay import at_master_messages, parameter_events
from cam_ros.recording.schedule import Schedule

from .recording_support import master, state, STREAM_TOPIC, StubRecording


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
    schedule = Schedule(events, lambda event: log.append(('set', event.time_ns)))
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


def test_an_ecam_change_moves_to_the_master_message_after_the_stamp_its_state_names():
    stamps = [7 * 10 ** 9 + 4_000_000 * k for k in range(12)]  # 250 Hz, logged 10 ns apart
    stream = [master(10 * (k + 1), stamp) for k, stamp in enumerate(stamps)]
    recording = StubRecording(stream + [
        state(1, 0, 'none'),  # at start-up: no change yet
        state(47, 1, stamps[3]),  # the first change was taken after the 4th message
        state(63, 1, stamps[3]),  # the switch word changed: the same change, said again
        state(66, 2, 'none'),  # taken before any master message: the event keeps its time
        state(64, 5, stamps[0], node='/other')])  # another node's changes are not this node's
    events = parameter_events([change(25, 'slave.offset', 0.001),  # logged before the 3rd
                               change(26, 'lift_m', 1.0, node='/other2'),  # no mark at all
                               change(60, 'slave.offset', 0.002),  # its mark (66) names no stamp
                               change(71, 'slave.offset', 0.003)])  # no mark after it: kept
    moved = at_master_messages(events, recording)
    # The first: before the 5th message (log 50), the first commanded with the new design.
    assert [(e.node, e.time_ns) for e in moved] == [('/cam', 50), ('/other2', 50),
                                                    ('/cam', 60), ('/cam', 71)]
    assert [e.changes for e in moved] == [e.changes for e in events]


def test_a_state_that_says_nothing_of_designs_moves_nothing():
    other = DiagnosticStatus(hardware_id='/cam', values=[KeyValue(key='switches', value='0')])
    recording = StubRecording([master(10, 5), master(20, 6),
                               RecordedMessage('/diagnostics_like', other, 15, 15)])
    events = parameter_events([change(12, 'slave.offset', 0.001)])
    assert at_master_messages(events, recording) == events
