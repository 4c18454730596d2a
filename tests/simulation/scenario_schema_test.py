"""docs/scenario.schema.json against the scenarios symdyn-sim loads: the schema
is valid JSON Schema (2020-12), every built-in scenario (models/scenarios) and
docs/scenarios.md's complete example satisfy it, and it refuses the mistakes
the loader refuses by structure (an unknown key, a wrong type, an unknown force
element type or output). Run by ctest with Debian's python3-jsonschema."""
import glob
import json
import os
import re
import sys

import jsonschema

root = sys.argv[1]
schema = json.load(open(os.path.join(root, "docs", "scenario.schema.json")))
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)

good = {path: json.load(open(path)) for path in glob.glob(os.path.join(root, "models", "scenarios", "*.json"))}
doc = open(os.path.join(root, "docs", "scenarios.md")).read()
good["docs/scenarios.md"] = json.loads(re.search(r"```json[^\n]*\n(\{.*?\n\})\n```", doc, re.S).group(1))
assert len(good) >= 6, sorted(good)
for name, scenario in good.items():
    errors = [e.message for e in validator.iter_errors(scenario)]
    assert not errors, (name, errors)

base = {"model": "double_pendulum"}
bad = [
    dict(base, t_ned=1),
    dict(base, t_end="10"),
    dict(base, t_end=-1),
    dict(base, forces=[{"type": "spring", "name": "s"}]),
    dict(base, forces=[{"type": "coordinate_spring_damper", "name": "s", "coordinate": "theta1", "stifness": 1}]),
    dict(base, forces=[{"type": "coordinate_force", "name": "has space", "coordinates": "theta1", "value": 1}]),
    dict(base, outputs=["qddd"]),
    dict(base, checks=[{"name": "c", "value": "end(theta1)", "band": [0]}]),
    dict(base, model={"name": "double_pendulum", "varient": "absolute"}),
    dict(base, events=[{"time": 1, "disabled": "motor"}]),
    {"t_end": 1},
    # constants of the sign their law needs
    dict(base, forces=[{"type": "plane_contact", "name": "c", "body": "rod2", "stiffness": 0}]),
    dict(base, forces=[{"type": "plane_contact", "name": "c", "body": "rod2", "stiffness": 1, "friction": -1}]),
    dict(base, forces=[{"type": "coordinate_spring_damper", "name": "s", "coordinate": "theta1", "stiffness": 1,
                        "damping": -1}]),
    dict(base, forces=[{"type": "bushing", "name": "b", "a": {"body": "ground"}, "b": {"body": "rod1"},
                        "stiffness": [1, -1, 1]}]),
    dict(base, forces=[{"type": "gim_tyre", "name": "w", "body": "rod2", "Kz": -1}]),
    dict(base, forces=[{"type": "simple_tyre", "name": "w", "body": "rod2", "axis": [0, 0, 0]}]),
    dict(base, forces=[{"type": "point_spring_damper", "name": "s", "a": {"body": "ground"}, "b": {"body": "rod2"},
                        "stiffness": 1}]),
    # shapes
    dict(base, shapes={"rod1": {"type": "cone", "radius": 1}}),
    dict(base, shapes={"rod1": {"type": "cylinder", "radius": 0.1}}),
    dict(base, shapes={"rod1": [{"type": "sphere", "radius": -0.1}]}),
    dict(base, shapes={"rod1": {"type": "box", "size": [1, 1]}}),
    dict(base, shapes={"rod1": {"type": "sphere", "radius": 0.1, "colour": "red"}}),
    dict(base, shapes={"rod1": {"type": "sphere", "radius": 0.1, "colour": [1, 0, 2]}}),
    dict(base, shapes={"rod1": {"type": "sphere", "radius": 0.1, "color": "#ff0000"}}),
]
for scenario in bad:
    assert not validator.is_valid(scenario), scenario
print(f"{len(good)} scenarios valid, {len(bad)} bad ones refused")
