"""Safe reading of parameters files: what is refused, how early, and what the error says."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from cam_ros.core import InvalidParameter
from cam_ros.core.config import params_file
from cam_ros.core.config.params_file import (MAX_ARRAY_LENGTH, MAX_DEPTH, MAX_FILE_BYTES,
                                             MAX_STRING_LENGTH, MAX_VALUES, parse_yaml,
                                             read_parameters_file, read_yaml)

BILLION_LAUGHS = '\n'.join(
    ['a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]']
    + [f'a{i}: &a{i} [{", ".join([f"*a{i - 1}"] * 9)}]' for i in range(1, 9)]
    + ['cam_speed: *a8'])


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / 'cam.yaml'
    path.write_text(text)
    return path


class Counting:
    """Count the nodes a loader composes and the objects it constructs (patched in)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch):
        self.composed = self.constructed = 0
        compose = params_file.Composer.compose_node
        construct = params_file._Loader.construct_object

        def counted_compose(loader, parent, index):
            self.composed += 1
            return compose(loader, parent, index)

        def counted_construct(loader, node, deep=False):
            self.constructed += 1
            return construct(loader, node, deep)

        monkeypatch.setattr(params_file.Composer, 'compose_node', counted_compose)
        monkeypatch.setattr(params_file._Loader, 'construct_object', counted_construct)


def test_a_plain_document_reads_as_yaml_does_with_ros_floats():
    text = 'a: 1\nb: [1.0, 2e3, x, true]\nc: {d: .5, e: -1e-3, f: 6.0e0}\n'
    assert parse_yaml(text) == {'a': 1, 'b': [1.0, 2000.0, 'x', True],
                                'c': {'d': 0.5, 'e': -0.001, 'f': 6.0}}


def test_an_alias_bomb_is_refused_at_its_first_anchor_before_anything_is_built(monkeypatch):
    counting = Counting(monkeypatch)
    with pytest.raises(InvalidParameter) as caught:
        parse_yaml(BILLION_LAUGHS, 'config', 'bomb.yaml')
    assert str(caught.value) == ("config = 'bomb.yaml': uses the YAML anchor or alias &a0 at "
                                 'line 1: parameters files may not use anchors or aliases')
    # The root mapping and the key a0 were composed; the anchored list never was, and no value
    # of the document was constructed: nothing could be expanded.
    assert (counting.composed, counting.constructed) == (2, 0)


def test_the_counting_patch_sees_a_normal_document():
    # Guards the test above: the same counters do count when nothing is refused.
    with pytest.MonkeyPatch.context() as patch:
        counting = Counting(patch)
        parse_yaml('a: [1, 2]\n')
    assert counting.composed == 5 and counting.constructed >= 1  # {a: [1, 2]}: 5 nodes


@pytest.mark.parametrize('text', ['a: &x 1\n', 'a: *x\n', 'a: [1, &x 2]\n', '? &k a\n: 1\n'])
def test_any_anchor_or_alias_is_refused(text):
    with pytest.raises(InvalidParameter, match='anchor or alias'):
        parse_yaml(text)


def test_a_duplicate_key_names_the_key_and_both_lines(tmp_path):
    text = ('/**:\n  ros__parameters:\n    follower:\n      roller_radius: 1.0\n'
            '      base_radius: 4.0\n      roller_radius: 3.5\n')
    with pytest.raises(InvalidParameter) as caught:
        read_parameters_file(write(tmp_path, text))
    assert str(caught.value) == ('follower.roller_radius = 3.5: is given twice, at lines 4 and '
                                 '6: give each key once')


def test_duplicates_are_found_in_flow_mappings_and_sections_but_not_across_mappings():
    with pytest.raises(InvalidParameter, match=r'^a = 2: is given twice, at lines 1 and 1'):
        parse_yaml('{a: 1, a: 2}')
    with pytest.raises(InvalidParameter, match=r"^s = \{'b': 2\}: is given twice, at lines 1 "):
        parse_yaml('s: {a: 1}\nt: 0\ns: {b: 2}\n')
    assert parse_yaml('s: {a: 1}\nt: {a: 2}\n') == {'s': {'a': 1}, 't': {'a': 2}}
    assert parse_yaml('{1: a, "1": b}') == {1: 'a', '1': 'b'}  # an int and a string key


def test_a_list_one_over_the_cap_is_refused_after_its_first_entries():
    entries = ', '.join(['0.5'] * (MAX_ARRAY_LENGTH + 1))
    text = f'/**:\n  ros__parameters:\n    motion:\n      start_deg: [{entries}]\n'
    with pytest.raises(InvalidParameter) as caught:
        parse_yaml(text)
    assert str(caught.value) == (f'motion.start_deg = [0.5, 0.5, 0.5, ...]: must have at most '
                                 f'{MAX_ARRAY_LENGTH} entries')
    assert parse_yaml(f'a: [{", ".join(["0.5"] * MAX_ARRAY_LENGTH)}]')['a'] == (
        [0.5] * MAX_ARRAY_LENGTH)


def test_a_huge_list_is_read_only_up_to_the_cap(monkeypatch):
    counting = Counting(monkeypatch)
    with pytest.raises(InvalidParameter, match='must have at most'):
        parse_yaml(f'a: [{", ".join(["1"] * 100 * MAX_ARRAY_LENGTH)}]')
    assert counting.composed == MAX_ARRAY_LENGTH + 3  # root, key, list, its first entries


def test_a_long_value_and_deep_nesting_and_many_values_are_refused():
    with pytest.raises(InvalidParameter) as caught:
        parse_yaml(f'x: {"y" * (MAX_STRING_LENGTH + 1)}')
    message = str(caught.value)
    assert message.endswith(f"yyy' ({MAX_STRING_LENGTH + 1} characters): must have at most "
                            f'{MAX_STRING_LENGTH} characters')
    assert len(message) < 200
    with pytest.raises(InvalidParameter, match=f'nests deeper than {MAX_DEPTH} levels'):
        parse_yaml('x: ' + '[' * 10**5)
    parse_yaml('x: ' + '[' * (MAX_DEPTH - 1) + ']' * (MAX_DEPTH - 1))
    with pytest.raises(InvalidParameter, match=f'holds more than {MAX_VALUES} values'):
        parse_yaml('{' + ', '.join(f'k{i}: 1' for i in range(MAX_VALUES)) + '}')


def test_a_file_over_the_size_cap_is_refused_unread(tmp_path):
    path = tmp_path / 'big.yaml'
    path.write_bytes(b'a: 1\n' + b'#' * MAX_FILE_BYTES)
    with pytest.raises(InvalidParameter) as caught:
        read_yaml(path)
    assert str(caught.value) == (f'config = {str(path)!r}: is larger than {MAX_FILE_BYTES} bytes,'
                                 ' the most a parameters file may hold')
    path.write_bytes(b'a: 1\n' + b'#' * (MAX_FILE_BYTES - 6) + b'\n')
    assert read_yaml(path) == {'a': 1}


@pytest.mark.parametrize('text, fragment', [
    ('a: [1\n', 'is not valid YAML at line 2, column 1: while parsing a flow sequence'),
    ('a: 1\n---\nb: 2\n', 'is not valid YAML at line 2, column 1'),
    ('a: !!python/object:os.system x\n', 'could not determine a constructor'),
])
def test_yaml_errors_are_one_line_with_the_position(text, fragment):
    with pytest.raises(InvalidParameter) as caught:
        parse_yaml(text, 'config', 'x.yaml')
    assert str(caught.value).startswith("config = 'x.yaml': ")
    assert fragment in str(caught.value) and '\n' not in str(caught.value)


def test_bytes_that_are_not_utf8_are_named(tmp_path):
    path = tmp_path / 'latin1.yaml'
    path.write_bytes('a: caf\u00e9\n'.encode('latin-1'))
    with pytest.raises(InvalidParameter, match=r'is not UTF-8 text \(byte 6\)'):
        read_yaml(path)


def test_sections_of_the_node_merge_in_file_order(tmp_path):
    text = ('/**:\n  ros__parameters: {a: 1, b: 1}\nother:\n  ros__parameters: {a: 9}\n'
            'cam:\n  ros__parameters: {b: 2, c: {d: 3}}\n')
    assert read_parameters_file(write(tmp_path, text)) == {'a': 1, 'b': 2, 'c.d': 3}
    assert read_parameters_file(write(tmp_path, text), ('other',)) == {'a': 9}


def ros_floats(value: object) -> object:
    """Read strings like 1e3, which YAML 1.1 leaves as text, as floats (as ROS does)."""
    if isinstance(value, dict):
        return {key: ros_floats(item) for key, item in value.items()}
    if isinstance(value, list):
        return [ros_floats(item) for item in value]
    if isinstance(value, str) and re.fullmatch(r'[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+', value):
        return float(value)
    return value


def test_the_loader_reads_what_pyyaml_reads_for_the_shipped_configs():
    for path in sorted((Path(__file__).resolve().parents[2] / 'config').glob('*.yaml')):
        assert read_yaml(path) == ros_floats(yaml.safe_load(path.read_text())), path.name
