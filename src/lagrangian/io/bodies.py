"""The fields of a 3-D rigid body in a model file: ``inertia`` as a 3x3 matrix or a shape,
``orientation`` as Euler angles, an axis and angle, a quaternion or a 3x3 matrix.

    inertia: [[A, 0, 0], [0, A, 0], [0, 0, C]]          # about the centre, body axes
    inertia: {shape: cylinder, radius: r, length: h}    # mass taken from the body
    orientation: {euler: ZXZ, angles: [phi, theta, psi]}   # intrinsic unless intrinsic: false
    orientation: {axis: [0, 0, 1], angle: theta}
    orientation: {quaternion: [q0, q1, q2, q3]}         # scalar first
    orientation: [[1, 0, 0], [0, "cos(a)", "-sin(a)"], [0, "sin(a)", "cos(a)"]]
    parent: gimbal                                      # relative to a body or a frame,
    rotations: [[z, psi], [x, theta], [z, phi]]         # by simple rotations about body axes

>>> import sympy as sp
>>> from lagrangian.io.document import Document
>>> from lagrangian.io.declarations import expression_names
>>> reader = Reader(Document({}, "<string>"), expression_names(["a"], []))
>>> read_orientation(reader, {"axis": [0, 0, 1], "angle": "a"}, "R").matrix[1, 0]
sin(a)
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.errors import ModelError
from lagrangian.io.document import child
from lagrangian.io.model_schema import entry_keys
from lagrangian.io.reader import Reader, describe, suggestion
from lagrangian.model.inertia import SHAPES, Shape, central_inertia, shape
from lagrangian.model.rotation import (
    AXIS_NAMES,
    EULER_SEQUENCES,
    Orientation,
    as_orientation,
    axis_angle,
    euler_rotation,
    quaternion_rotation,
)

_EXAMPLE_MATRIX = "[[A, 0, 0], [0, A, 0], [0, 0, C]]"
#: The key naming each mapping form of an orientation -> the keys that form has.
_FORM_KEYS = {
    "euler": ("euler", "angles", "intrinsic"),
    "axis": ("axis", "angle"),
    "quaternion": ("quaternion",),
}


def read_matrix(reader: Reader, value: Any, path: str) -> sp.ImmutableMatrix | None:
    """A 3x3 matrix written as three rows of three expressions."""
    rows = reader.items(value, path)
    if len(rows) != 3 or not all(isinstance(r, list) and len(r) == 3 for r in rows):
        sizes = ", ".join(str(len(r)) if isinstance(r, list) else describe(r) for r in rows)
        reader.problem(
            path,
            f"a 3x3 matrix needs 3 rows of 3 expressions, got rows of {sizes}",
            "write " + _EXAMPLE_MATRIX,
        )
        return None
    entries = [reader.vector(row, child(path, i)) for i, row in enumerate(rows)]
    if any(e is None for e in entries):
        return None
    return sp.ImmutableMatrix([list(row) for row in entries if row is not None])


def read_inertia(reader: Reader, value: Any, path: str) -> Any:
    """A scalar (planar body), a 3x3 matrix or a shape mapping."""
    if isinstance(value, list):
        return read_matrix(reader, value, path)
    if isinstance(value, dict):
        return _read_shape(reader, value, path)
    return reader.expression(value, path)


def about_the_centre(reader: Reader, values: dict[str, Any], path: str) -> dict[str, Any] | None:
    """The fields of a rigid body whose ``inertia`` is given about the body point
    ``inertia_about`` (from the centre of mass, body axes), with the inertia about the centre
    instead (the parallel-axis theorem, :func:`lagrangian.model.inertia.central_inertia`); a
    planar body's scalar I_P gives I_c = I_P - m |d|^2.  None after a recorded problem."""
    values = dict(values)
    offset, inertia, mass = values.pop("inertia_about"), values.get("inertia"), values.get("mass")
    if inertia is None or mass is None:
        return values  # the missing field is reported as such
    if isinstance(inertia, Shape):
        reader.problem(path, "a shape's inertia is about its centre", "leave out inertia_about")
        return None
    if isinstance(inertia, sp.MatrixBase):
        if len(offset) != 3:
            reader.problem(path, "a 3x3 inertia needs a point [dx, dy, dz]", "give three values")
            return None
        values["inertia"] = central_inertia(inertia, mass, [-d for d in offset])
        return values
    if len(offset) != 2:
        reader.problem(path, "a planar body's point is [dx, dy]", "give two values")
        return None
    values["inertia"] = sp.expand(inertia - mass * (offset[0] ** 2 + offset[1] ** 2))
    return values


def _read_shape(reader: Reader, value: dict[str, Any], path: str) -> Shape | None:
    """``{shape: KIND, DIMENSION: expression, ..., axis: x|y|z}``; every problem recorded."""
    before = len(reader.problems)
    entry = reader.entry(value, path, "shape")  # reports keys no shape has
    if entry is None or "shape" not in entry:
        return None
    kind = entry["shape"]
    if not isinstance(kind, str) or kind not in SHAPES:
        fix = suggestion(str(kind), SHAPES, "use one of " + ", ".join(SHAPES))
        reader.problem(child(path, "shape"), f"unknown shape {describe(kind)}", fix)
        return None
    _, names, axial = SHAPES[kind]
    has = f"a {kind} has {', '.join(names)}"
    known = set(entry_keys("shape").allowed)
    for key in sorted(set(entry) & known - {"shape", "axis", *names}):
        reader.problem(child(path, key), f"a {kind} has no {key}", has, key=True)
    if set(entry) <= known:  # a misspelt dimension was reported as such
        for key in names:
            if key not in entry:
                reader.problem(path, f"a {kind} needs its {key}", has)
    dimensions = {
        key: reader.expression(entry[key], child(path, key)) for key in names if key in entry
    }
    axis = entry.get("axis", "z")
    if axis not in ("x", "y", "z") or (axis != "z" and not axial):
        fix = "give x, y or z" if axial else f"a {kind} has no axis to choose"
        reader.problem(child(path, "axis"), f"axis {describe(axis)} is not allowed", fix)
    if len(reader.problems) > before:
        return None
    return shape(kind, axis=axis, **dimensions)


def read_orientation(reader: Reader, value: Any, path: str) -> Orientation | None:
    """Euler angles, an axis and angle, a quaternion (mappings) or a 3x3 matrix (a list)."""
    if isinstance(value, list):
        matrix = read_matrix(reader, value, path)
        return None if matrix is None else as_orientation(matrix)
    entry = reader.entry(value, path, "rotation")
    if entry is None:
        return None
    example = "write e.g. {euler: ZXZ, angles: [phi, theta, psi]} or a 3x3 matrix"
    form = reader.one_of(entry, _FORM_KEYS, path, "an orientation", example)
    if form is None:
        return None
    own = _FORM_KEYS[form]
    known = set(entry_keys("rotation").allowed)  # other keys: reported by reader.entry
    for key in sorted(set(entry) & known - set(own)):
        fix = f"with {form}, give " + ", ".join(own)
        reader.problem(child(path, key), f"{key!r} does not belong here", fix, key=True)
    try:
        return _build_orientation(reader, entry, path, form)
    except ModelError as exc:  # a bad sequence or a zero axis, found by the model
        for problem in exc.problems:
            reader.problem(child(path, problem.field), problem.message, problem.fix)
        return None


def _build_orientation(
    reader: Reader, entry: dict[str, Any], path: str, form: str
) -> Orientation | None:
    if form == "quaternion":
        parts = _sized(reader, entry["quaternion"], child(path, "quaternion"), 4, "[w, x, y, z]")
        return None if parts is None else quaternion_rotation(*parts)
    if form == "axis":
        axis = _sized(reader, entry["axis"], child(path, "axis"), 3, "[0, 0, 1]")
        angle = _required_expression(reader, entry, path, "angle", "the angle of rotation")
        return None if axis is None or angle is None else axis_angle(axis, angle)
    sequence = entry["euler"]
    if not isinstance(sequence, str) or sequence.upper() not in EULER_SEQUENCES:
        fix = suggestion(str(sequence).upper(), EULER_SEQUENCES, "use e.g. ZXZ or ZYX")
        reader.problem(child(path, "euler"), f"unknown Euler sequence {describe(sequence)}", fix)
        return None
    angles = None
    if "angles" not in entry:
        reader.problem(path, "Euler angles need their angles", "add angles: [a, b, c]")
    else:
        angles = _sized(reader, entry["angles"], child(path, "angles"), 3, "[phi, theta, psi]")
    intrinsic = entry.get("intrinsic", True)
    if not isinstance(intrinsic, bool):
        where = child(path, "intrinsic")
        reader.problem(where, f"must be true or false, got {describe(intrinsic)}", "give false")
        return None
    return None if angles is None else euler_rotation(sequence, angles, intrinsic=intrinsic)


def read_axis(reader: Reader, value: Any, path: str) -> str | tuple[sp.Expr, ...] | None:
    """An axis: x, y or z (body axes; any other name is judged by the model, which names
    the body) or a vector of 3 expressions."""
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        return _sized(reader, value, path, 3, "[0, 0, 1]")
    reader.problem(path, f"{describe(value)} is not an axis", "give x, y, z or [a, b, c]")
    return None


def read_rotations(reader: Reader, value: Any, path: str) -> tuple[Any, ...] | None:
    """Simple rotations ``[[axis, angle], ...]`` about successive body axes."""
    turns = []
    for k, item in enumerate(reader.items(value, path)):
        where = child(path, k)
        if not (isinstance(item, list) and len(item) == 2):
            example = "write [axis, angle] with axis " + ", ".join(AXIS_NAMES) + ", e.g. [z, psi]"
            reader.problem(where, f"{describe(item)} is not one rotation", example)
            return None
        axis = read_axis(reader, item[0], child(where, 0))
        angle = reader.expression(item[1], child(where, 1))
        if axis is None or angle is None:
            return None
        turns.append((axis, angle))
    return tuple(turns)


def _sized(reader: Reader, value: Any, path: str, size: int, example: str) -> Any:
    components = reader.vector(value, path)
    if components is not None and len(components) != size:
        message = f"needs {size} components, got {len(components)}"
        reader.problem(path, message, f"give {example}")
        return None
    return components


def _required_expression(
    reader: Reader, entry: dict[str, Any], path: str, key: str, what: str
) -> sp.Expr | None:
    if key not in entry:
        reader.problem(path, f"missing {key} ({what})", f"add {key}")
        return None
    return reader.expression(entry[key], child(path, key))
