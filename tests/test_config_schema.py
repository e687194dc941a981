"""The JSON schema of a ``navigate`` configuration (``memsnav schema``,
docs/reference/navigate.schema.json), checked by an independent validator
(``jsonschema``): every shipped navigate example passes it, and it refuses
what the loader refuses for a key's kind (a misspelt key or table, a value
of the wrong kind or out of bounds, a required key left out)."""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path

import jsonschema
import pytest
import tomli_w

from memsnav.cli import main
from memsnav.realdata.config import json_schema, load_config

ROOT = Path(__file__).resolve().parents[1]
NAVIGATE_EXAMPLES = [
    p
    for p in sorted((ROOT / "examples").glob("*.toml"))
    if not {"session", "study"} & tomllib.loads(p.read_text()).keys()
]


@pytest.fixture(scope="module")
def validator():
    schema = json_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("example", NAVIGATE_EXAMPLES, ids=lambda p: p.stem)
def test_every_navigate_example_is_valid(validator, example):
    errors = [e.message for e in validator.iter_errors(tomllib.loads(example.read_text()))]
    assert not errors, errors


#: Changes to a valid configuration that the schema and the loader both
#: refuse: (table, key, value); value None deletes the key.
REFUSED = [
    ("filter", "gate_probabilty", 0.99),  # misspelt key
    ("filtr", "gate_probability", 0.99),  # misspelt table
    ("filter", "gate_probability", 1.5),  # above its bound
    ("filter", "installation_states", "yes"),  # a flag as text
    ("gnss", "range_bias_states", "every"),  # not the one word it takes
    ("gnss", "mode", "tightly"),  # not a choice
    ("imu", "lever_arm_m", [0.1, 0.2]),  # two numbers for three
    ("outages", "keep_satellites", 4),  # out of its range
    ("aids", "nhc_std_m_s", -0.1),  # negative
    ("imu", "file", None),  # required
]


@pytest.mark.parametrize("table,key,value", REFUSED, ids=lambda x: str(x))
def test_the_schema_refuses_what_the_loader_refuses(validator, tmp_path, table, key, value):
    example = ROOT / "examples" / "drive_0708.toml"
    config = tomllib.loads(example.read_text())
    changed = copy.deepcopy(config)
    if value is None:
        del changed[table][key]
    else:
        changed.setdefault(table, {})[key] = value
    assert list(validator.iter_errors(changed)), (table, key, value)
    path = tmp_path / "changed.toml"
    path.write_text(tomli_w.dumps(changed))
    with pytest.raises(ValueError, match=key if table != "filtr" else table):
        load_config(path, data_root=ROOT.parent / "shared" / "data")


def test_the_command_writes_the_shipped_schema(tmp_path, capsys):
    """``memsnav schema --output`` writes docs/reference/navigate.schema.json
    as shipped, and without ``--output`` prints it."""
    out = tmp_path / "navigate.schema.json"
    assert main(["schema", "--output", str(out)]) == 0
    shipped = ROOT / "docs" / "reference" / "navigate.schema.json"
    assert out.read_text() == shipped.read_text()
    capsys.readouterr()
    assert main(["schema"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads(shipped.read_text())
