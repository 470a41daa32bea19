"""A small scene of lookalikes' meshes grouped into families, for the bench smoke tests of look-alike tools.

    python3 family_scene.py LOOKALIKES.json OUT.json NAME OBJECT:FAMILY[:RENAME] ...

Each argument takes the lookalikes object OBJECT (its mesh path made absolute) into family FAMILY, renamed RENAME
when given (two copies of one mesh need two names). The pairing share of the lookalikes scene is dropped, so that a
map trained on a few readings pairs them all.
"""

import json
import os
import sys

source, out, name, *members = sys.argv[1:]
scene = json.load(open(source))
objects = os.path.join(os.path.dirname(os.path.abspath(source)), "..", "objects")
by_name = {o["name"]: o for o in scene["objects"]}
scene["name"] = name
scene["objects"] = []
for spec in members:
    obj, family, *rename = spec.split(":")
    o = dict(by_name[obj], family=family, mesh=os.path.join(objects, os.path.basename(by_name[obj]["mesh"])))
    if rename:
        o["name"] = rename[0]
    scene["objects"].append(o)
scene.setdefault("appearance", {}).pop("pair_readings", None)
json.dump(scene, open(out, "w"))
