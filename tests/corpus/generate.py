#!/usr/bin/env python3
"""Regenerate the hostile-input corpus of tests/hostile.rs: case files under cases/,
assets (EXR images, a shard partial) under assets/, hostile shard partials under merge/,
export folders (export.json, case.json, renders) for judge under export/, and manifest.json listing every input with its expected outcome.

    python3 tests/corpus/generate.py

Each manifest entry: name, class (crash | hang | wrong | unclear | leftover | f32 |
baseline), args (placeholders: {corpus} this folder, {tmp} a fresh folder per entry,
{empty_dir} an empty folder, {big} a sparse file past the JSON size limit, {big_asset} a
sparse `.exr` past the 1 GiB asset limit, {fifo} a named pipe with no writer, {file} an
existing regular file, {dangling} a symbolic link to a missing target), and either expect 2 with `field` (and optionally `contains`), a
substring the one stderr line must hold (and optionally `absent`, one it must not), or
expect "valid" (exit 0 or 1; for estimate a finite `estimate` on stdout; for merge, case
reports whose every point has a finite `estimate` and `seconds`). `pre_files` are
created in {tmp} first; `no_leftovers` asks that no `.tmp` file remain in {tmp}
afterwards. `sweep` ({group, value}) marks the entries of one numeric field swept over
every value of EXTREMES (hostile.rs checks that no sweep misses one).
"""
import copy, json, os, struct, shutil

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLES = ["--samples", "4096"]

# ---------------------------------------------------------------- assets
def exr(width, height, pixels, claim=None, offsets=True):
    """An uncompressed scanline RGB float EXR; `claim` overrides the data window."""
    def attr(name, typ, data):
        return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(data)) + data
    ch = b"".join(c.encode() + b"\0" + struct.pack("<i", 2) + b"\0\0\0\0" + struct.pack("<ii", 1, 1)
                  for c in "BGR") + b"\0"
    w, h = claim or (width, height)
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2)
              + attr("channels", "chlist", ch)
              + attr("compression", "compression", b"\0")
              + attr("dataWindow", "box2i", box)
              + attr("displayWindow", "box2i", box)
              + attr("lineOrder", "lineOrder", b"\0")
              + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
              + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
              + b"\0")
    if not offsets:
        return header
    chunks = []
    for y in range(height):
        row = pixels[y * width:(y + 1) * width]
        data = b"".join(struct.pack("<%df" % width, *[p[c] for p in row]) for c in (2, 1, 0))
        chunks.append(struct.pack("<ii", y, len(data)) + data)
    start = len(header) + 8 * height
    table, pos = b"", start
    for c in chunks:
        table += struct.pack("<Q", pos)
        pos += len(c)
    return header + table + b"".join(chunks)

def write(path, data):
    path = os.path.join(HERE, path)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)

# Case files are all rewritten: clear the old ones first, so that none outlives its entry.
if __name__ == "__main__":
    for old in os.listdir(os.path.join(HERE, "cases")):
        if old.endswith(".json"):
            os.remove(os.path.join(HERE, "cases", old))

# ---------------------------------------------------------------- base cases
DISK = {
    "name": "disk on axis", "teaches": "E = pi L R^2/(R^2 + h^2)",
    "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 1},
                          "emission": {"radiance": 1}}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "estimators": ["light", "mis"]}
POINT = {
    "name": "point light", "teaches": "E = I cos/r^2",
    "scene": {"emitters": [{"type": "point", "position": [0.5, -0.4, 2], "intensity": 3}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0.3, 0.2, 1]}},
    "estimators": ["light"]}
SPOT = {
    "name": "spot light", "teaches": "inside the inner cone a spot is a point light",
    "scene": {"emitters": [{"type": "spot", "position": [0.2, 0.1, 3], "direction": [0, 0, -1], "intensity": 5,
                            "cone_angle": 30, "falloff_start": 20}]},
    "measure": {"irradiance": {"at": [0.5, -0.3, 0], "normal": [0, 0.2, 1]}},
    "estimators": ["light"]}
SKY = {
    "name": "sky and sun", "teaches": "E = pi L + E_sun cos",
    "scene": {"emitters": [{"type": "constant", "radiance": 1.25},
                           {"type": "directional", "direction": [0, 0, -1], "irradiance": 2}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "estimators": ["mis"]}
ENV = {
    "name": "envmap sky", "teaches": "a lat-long map of radiance 1 gives E = pi",
    "scene": {"emitters": [{"type": "envmap", "path": "../assets/env_ok.exr", "scale": 1}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "estimators": ["mis"]}
SHAPES = {
    "name": "shapes", "teaches": "every geometry type, transformed",
    "scene": {"materials": {"white": {"type": "lambertian", "albedo": 0.5}},
              "shapes": [
                  {"geometry": {"type": "sphere", "center": [0, 0, 3], "radius": 0.5}, "material": "white",
                   "emission": {"radiance": 1}},
                  {"geometry": {"type": "rectangle", "corner": [-1, -1, 4], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0]},
                   "material": "white"},
                  {"geometry": {"type": "triangle", "vertices": [[2, 0, 2], [3, 0, 2], [2, 1, 2]]},
                   "emission": {"radiance": 2, "two_sided": True}},
                  {"geometry": {"type": "mesh", "vertices": [[-3, 0, 2], [-2, 0, 2], [-2, 1, 2], [-3, 1, 2]],
                                "indices": [[0, 1, 2], [0, 2, 3]]}, "material": "white"},
                  {"geometry": {"type": "disk", "center": [0, 3, 2], "normal": [0, 0, -1], "radius": 0.5},
                   "transform": {"scale": 2, "rotate": {"axis": [0, 0, 1], "degrees": 30}, "translate": [0, 0, 1]},
                   "emission": {"radiance": 1}}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "estimators": ["mis"]}
SPECTRAL = {
    "name": "blackbody band", "teaches": "band radiance of a blackbody disk",
    "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 4},
                          "emission": {"radiance": 1, "spectrum": {"blackbody": {"temperature": 3000}}}}]},
    "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
    "spectral": {"band": [380, 780], "sampling": "uniform", "hero": True},
    "estimators": ["light"]}
BK7 = {
    "name": "bk7 slab", "teaches": "a dispersive slab",
    "scene": {"materials": {"glass": {"type": "dielectric", "eta": 1.5}},
              "dispersion": {"glass": {"eta": {"sellmeier": {"b": [1.03961212, 0.231792344, 1.01046945],
                                                              "c": [0.00600069867, 0.0200179144, 103.560653]}}}},
              "shapes": [
                  {"geometry": {"type": "rectangle", "corner": [-10, -10, 1], "edge_u": [0, 20, 0], "edge_v": [20, 0, 0]},
                   "material": "glass"},
                  {"geometry": {"type": "rectangle", "corner": [-10, -10, 1.1], "edge_u": [20, 0, 0], "edge_v": [0, 20, 0]},
                   "material": "glass"},
                  {"geometry": {"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 20},
                   "emission": {"radiance": 1}}]},
    "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
    "spectral": {"band": [400, 700], "sampling": "uniform"},
    "estimators": ["mis"]}
METAL = {
    "name": "metal mirror", "teaches": "a conductor under a sky",
    "scene": {"materials": {"metal": {"type": "conductor", "eta": 0.2, "k": 3.9}},
              "dispersion": {"metal": {"k": 3.9}},
              "shapes": [{"geometry": {"type": "rectangle", "corner": [-5, -5, 1], "edge_u": [10, 0, 0], "edge_v": [0, 10, 0]},
                          "material": "metal"}],
              "emitters": [{"type": "constant", "radiance": 1}]},
    "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
    "estimators": ["mis"]}
PULSE = {
    "name": "pulsed disk", "teaches": "arrivals in a time bin",
    "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 1},
                          "emission": {"radiance": 1, "pulse_at": 0}}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "time": {"bin": [3.6692050471796728e-09, 4.336333237575977e-09]},
    "estimators": ["light"]}
MOVING = {
    "name": "moving point light", "teaches": "shutter average",
    "scene": {"emitters": [{"type": "point", "position": [0, 0, 2], "intensity": 3, "velocity": [1.5, 0, 0]}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "time": {"shutter": [-0.5, 2]},
    "estimators": ["light"]}
ALBEDO = {
    "name": "albedo", "teaches": "a rough conductor's albedo",
    "measure": {"albedo": {"bsdf": {"type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9}, "theta_degrees": 60}},
    "estimators": ["bsdf"]}
CHORD = {
    "name": "mean chord", "teaches": "4V/S",
    "scene": {"shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1.5}}]},
    "measure": {"mean_path_length": {"shape": 0, "segments": 8}},
    "estimators": ["cosine"]}
POWER = {
    "name": "sphere power", "teaches": "Phi = pi L A",
    "scene": {"shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1}, "emission": {"radiance": 1}}]},
    "measure": {"power": {"shape": 0}},
    "estimators": ["uniform"]}
REF = dict(DISK, reference={"closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1})
CAMERA = dict(DISK, camera={"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 60,
                            "width": 8, "height": 6})

ENTRIES = []

def case(name, cls, base, edits, expect, field=None, contains=None, cmd="estimate", extra=None, raw=None, **more):
    """A case file: `base` with `edits` ((path, value) pairs; value DELETE removes the key)."""
    doc = copy.deepcopy(base)
    for path, value in edits:
        keys = path.split(".")
        node = doc
        for k in keys[:-1]:
            node = node[int(k)] if isinstance(node, list) else node[k]
        last = keys[-1]
        if isinstance(node, list):
            node[int(last)] = copy.deepcopy(value)
        elif value is DELETE:
            del node[last]
        else:
            node[last] = copy.deepcopy(value)
    text = raw if raw is not None else json.dumps(doc, indent=1)
    write("cases/%s.json" % name, text)
    args = [cmd, "{corpus}/cases/%s.json" % name]
    if cmd == "estimate":
        args += SAMPLES
    elif cmd == "verify":
        args += ["--samples", "4096", "--no-chi2"]
    elif cmd == "render":
        args += ["--spp", "1", "-o", "{tmp}/out.exr"]
    entry(name, cls, args + (extra or []), expect, field, contains, **more)

def entry(name, cls, args, expect, field=None, contains=None, **more):
    e = {"name": name, "class": cls, "args": args, "expect": expect}
    if field:
        e["field"] = field
    if contains:
        e["contains"] = contains
    e.update(more)
    ENTRIES.append(e)

class Delete:
    pass
DELETE = Delete()

# Every numeric field is swept over these values (hostile.rs checks that each sweep holds
# all of them): -1, 0, a subnormal of f32 (1e-39, which f32 keeps as a subnormal), the
# smallest subnormal of f64 (5e-324, which f32 flushes to 0), 1e39 (past f32's 3.4e38),
# 1e308 and a string.
SUB = 1e-39         # a subnormal f32
SUB64 = 5e-324      # the smallest subnormal f64
EXTREMES = [("m1", -1), ("zero", 0), ("sub", SUB), ("sub64", SUB64), ("e39", 1e39), ("e308", 1e308),
            ("str", "NaN")]
LABELS = [label for label, _ in EXTREMES]

def sweep(prefix, base, path, field, outcomes, cmd="estimate", vec=None, fields=None, contains=None, edits=()):
    """Numeric field `path` at every value of EXTREMES. `outcomes` maps each label (all of
    them: a sweep is complete) to 2 or "valid"; `vec` = (index, vector) puts the value in
    one component; `fields` and `contains` map a label to the field named in its message
    (default `field`) and a substring it must hold; `edits` apply to every value."""
    assert sorted(outcomes) == sorted(LABELS), "%s: sweep every value, not %s" % (prefix, sorted(outcomes))
    for label, v in EXTREMES:
        exp = outcomes[label]
        value = v
        if vec is not None:
            i, base_vec = vec
            value = list(base_vec)
            value[i] = v
        cls = "f32" if label in ("sub", "sub64", "e39", "e308") else "baseline"
        f = (fields or {}).get(label, field)
        case("%s_%s" % (prefix, label), cls, base, list(edits) + [(path, value)], exp,
             f if exp == 2 else None, (contains or {}).get(label) if exp == 2 else None, cmd=cmd,
             sweep={"group": prefix, "value": label})

def outcomes(default, **labels):
    """Every label at `default` but those given."""
    return dict({label: default for label in LABELS}, **labels)

# f32 quantities: any value that fits f32 (0 included) / non-negative / positive.
SIGNED = outcomes(2, m1="valid", zero="valid")
NONNEG = outcomes(2, zero="valid")
POS = ALL2 = outcomes(2)
# A coordinate component: within ±1e18, subnormals allowed.
COORD = outcomes(2, m1="valid", zero="valid", sub="valid", sub64="valid")
# The one non-zero component of a direction: a zero or subnormal vector cannot be normalised.
DIRZ = outcomes(2, m1="valid")
# A component of a direction beside a non-zero one: anything finite within f32.
DIRX = COORD

# ---------------------------------------------------------------- scene.shapes
sweep("emission_radiance", DISK, "scene.shapes.0.emission.radiance", "scene.shapes[0].emission.radiance", NONNEG)
sweep("disk_radius", DISK, "scene.shapes.0.geometry.radius", "scene.shapes[0].geometry.radius", POS)
sweep("disk_center", DISK, "scene.shapes.0.geometry.center", "scene.shapes[0].geometry.center", COORD,
      vec=(2, [0, 0, 2]))
sweep("disk_normal", DISK, "scene.shapes.0.geometry.normal", "scene.shapes[0].geometry.normal", DIRZ,
      vec=(2, [0, 0, -1]))
sweep("sphere_radius", SHAPES, "scene.shapes.0.geometry.radius", "scene.shapes[0].geometry.radius", POS)
case("radius_1e308_message", "unclear", DISK, [("scene.shapes.0.geometry.radius", 1e308)], 2,
     "scene.shapes[0].geometry.radius", "overflows")
case("radius_1e30_message", "unclear", SHAPES, [("scene.shapes.0.geometry.radius", 1e30)], 2,
     "scene.shapes[0].geometry.radius", "too large")
# A sphere whose area 4πr² is subnormal in f32 (r = 1e-20: 1.3e-39): its area density
# 1/A overflowed and every sample came out NaN. Rejected; r = 1e-10 stays valid.
case("sphere_radius_area_subnormal", "f32", SHAPES, [("scene.shapes.0.geometry.radius", 1e-20)], 2,
     "scene.shapes[0].geometry", "too small")
case("sphere_radius_tiny_valid", "f32", SHAPES, [("scene.shapes.0.geometry.radius", 1e-10)], "valid")
# Planar shapes far beyond unit scale: a mesh whose edges are 1e-15 (the f32 square of its
# normal underflowed: called degenerate, and never hit) and a triangle light 1e14 across
# (its f32 edge-function products overflowed into NaN distances). Both valid.
case("mesh_vertices_tiny_valid", "f32", SHAPES,
     [("scene.shapes.3.geometry.vertices", [[-3e-15, 0, 2e-15], [-2e-15, 0, 2e-15], [-2e-15, 1e-15, 2e-15], [-3e-15, 1e-15, 2e-15]])],
     "valid")
# The lone `triangle` shape was called degenerate where the mesh's same triangle was not:
# its check took the f32 length of the cross product, whose square underflows for edges
# below ~1e-11. Both now ask only that the f32 cross product be nonzero (and the f64 one's
# length positive): edges of 1e-15 are valid, edges of 1e-25 (cross product 1e-50, zero
# in f32) are refused.
case("triangle_vertices_tiny_valid", "f32", SHAPES,
     [("scene.shapes.2.geometry.vertices", [[2e-15, 0, 2e-15], [3e-15, 0, 2e-15], [2e-15, 1e-15, 2e-15]])], "valid")
case("triangle_vertices_f32_zero_area", "f32", SHAPES,
     [("scene.shapes.2.geometry.vertices", [[2e-25, 0, 2e-25], [3e-25, 0, 2e-25], [2e-25, 1e-25, 2e-25]])], 2,
     "scene.shapes[2].geometry", "zero area")
case("triangle_vertices_huge_valid", "f32", SHAPES,
     [("scene.shapes.2.geometry.vertices", [[2e14, 0, 2e14], [3e14, 0, 2e14], [2e14, 1e14, 2e14]])], "valid")
sweep("sphere_center", SHAPES, "scene.shapes.0.geometry.center", "scene.shapes[0].geometry.center", COORD, vec=(0, [0, 0, 3]))
sweep("rect_corner", SHAPES, "scene.shapes.1.geometry.corner", "scene.shapes[1].geometry.corner", COORD,
      vec=(2, [-1, -1, 4]))
sweep("rect_edge", SHAPES, "scene.shapes.1.geometry.edge_u", "scene.shapes[1].geometry.edge_u", DIRX,
      vec=(1, [2, 0, 0]))
# edge_v's only non-zero component: at 0 or a subnormal the rectangle has no (f32) area.
RG = "scene.shapes[1].geometry"
sweep("rect_edge_v", SHAPES, "scene.shapes.1.geometry.edge_v", RG + ".edge_v", DIRZ, vec=(1, [0, 2, 0]),
      fields={"zero": RG, "sub": RG, "sub64": RG})
sweep("triangle_vertex", SHAPES, "scene.shapes.2.geometry.vertices.1", "scene.shapes[2].geometry.vertices", COORD,
      vec=(0, [3, 0, 2]))
sweep("mesh_vertex", SHAPES, "scene.shapes.3.geometry.vertices.0", "scene.shapes[3].geometry.vertices", COORD,
      vec=(1, [-3, 0, 2]))
# Vertex indices are integers: 0 makes the first triangle degenerate, the rest are not indices.
sweep("mesh_index", SHAPES, "scene.shapes.3.geometry.indices.0", "scene.shapes[3].geometry.indices", ALL2,
      vec=(2, [0, 1, 2]))
sweep("transform_scale", SHAPES, "scene.shapes.4.transform.scale", "scene.shapes[4].transform.scale", POS)
sweep("transform_translate", SHAPES, "scene.shapes.4.transform.translate", "scene.shapes[4].transform.translate",
      COORD, vec=(2, [0, 0, 1]))
sweep("rotate_degrees", SHAPES, "scene.shapes.4.transform.rotate.degrees", "scene.shapes[4].transform.rotate.degrees",
      SIGNED)
sweep("rotate_axis", SHAPES, "scene.shapes.4.transform.rotate.axis", "scene.shapes[4].transform.rotate.axis", DIRZ,
      vec=(2, [0, 0, 1]))
case("transform_scale_1e20", "f32", SHAPES, [("scene.shapes.4.transform.scale", 1e20)], 2,
     "scene.shapes[4].geometry.radius", "too large")
case("radius_3e38_power", "f32", DISK, [("scene.shapes.0.emission.radiance", 3e38)], 2,
     "scene.shapes[0].emission.radiance", "power")
MOVING_SHAPE = dict(MOVING, scene=dict(MOVING["scene"], shapes=[
    {"geometry": {"type": "sphere", "center": [0, 0, 5], "radius": 1}, "velocity": [0.5, 0, 0]}]))
sweep("shape_velocity", MOVING_SHAPE, "scene.shapes.0.velocity", "scene.shapes[0].velocity", COORD,
      vec=(0, [0.5, 0, 0]))
case("mesh_index_out_of_range", "baseline", SHAPES, [("scene.shapes.3.geometry.indices", [[0, 1, 9]])], 2,
     "scene.shapes[3].geometry.indices[0]")
case("mesh_index_negative", "baseline", SHAPES, [("scene.shapes.3.geometry.indices", [[0, 1, -1]])], 2,
     "scene.shapes[3].geometry.indices")
# A triangle whose corners differ in f64 but not in f32 (10⁸ + 1 rounds to 10⁸): its f64
# normal is fine, its f32 cross product, which the hit test uses, is 0. Refused.
for name, corners in [("mesh_degenerate_in_f32", [[1e8, 0, 2], [100000001, 0, 2], [1e8, 1, 2]]),
                      ("mesh_degenerate_in_f32_third_corner", [[1e8, 0, 2], [1e8, 1, 2], [100000001, 0, 2]])]:
    case(name, "f32", SHAPES, [("scene.shapes.3.geometry", {"type": "mesh", "vertices": corners,
                                                             "indices": [[0, 1, 2]]})], 2,
         "scene.shapes[3].geometry.indices[0]", "degenerate")
# And one exactly collinear in f64 (the second edge is 11 times the first, every product
# exact) whose f32 rounding is not (its f32 cross product is 3·10⁻⁵): zero area, refused
# by its f64 normal.
case("mesh_collinear_in_f64_only", "f32", dict(SHAPES, measure={"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}}),
     [("scene.shapes.3.geometry", {"type": "mesh", "vertices": [[0, 0, 2], [31, 1.1049774046987295, 2],
                                                                [341, 12.154751451686025, 2]], "indices": [[0, 1, 2]]})],
     2, "scene.shapes[3].geometry.indices[0]", "degenerate")
case("obj_dev_zero", "hang", SHAPES, [("scene.shapes.3.geometry", {"type": "obj", "path": "/dev/zero"})], 2,
     "scene.shapes[3].geometry.path", "regular file")
case("obj_missing", "baseline", SHAPES, [("scene.shapes.3.geometry", {"type": "obj", "path": "nope.obj"})], 2,
     "scene.shapes[3].geometry.path")
# An OBJ's `mtllib` names files the loader once opened itself, unchecked: `/dev/zero` ran
# it out of memory (abort), a FIFO hung it. Materials are the case's own: none is read.
# Points and lines bound no area: left out (they were zero-area triangles, refused).
OBJ_ASSETS = {
    "obj_mtllib_dev_zero": "mtllib /dev/zero\nv -3 0 2\nv -2 0 2\nv -2 1 2\nf 1 2 3\n",
    "obj_points_and_lines": "v -3 0 2\nv -2 0 2\nv -2 1 2\nf 1 2 3\nl 1 2\np 3\nf 1 2\n",
    "obj_lines_only": "v -3 0 2\nv -2 0 2\nl 1 2\n",
    "obj_degenerate_face": "v -3 0 2\nv -2 0 2\nv -1 0 2\nv -2 1 2\nf 1 2 4\nf 1 2 3\n",
}
for name, outcome, contains in [
    ("obj_mtllib_dev_zero", "valid", None),
    ("obj_points_and_lines", "valid", None),
    ("obj_lines_only", 2, "a mesh needs at least one triangle"),
    ("obj_degenerate_face", 2, "triangle 1 (counting from 0, polygons split into triangles) is a degenerate"),
]:
    case(name, "crash" if name == "obj_mtllib_dev_zero" else "unclear", SHAPES,
         [("scene.shapes.3.geometry", {"type": "obj", "path": "../assets/%s.obj" % name})], outcome,
         "scene.shapes[3].geometry.path" if outcome == 2 else None, contains)
# A pulse at -1 s puts the bin 1 s after it, where its 0.67 ns is too narrow for f32 path
# lengths (1e-4 of the time since the pulse): refused naming `time.bin`.
sweep("pulse_at", PULSE, "scene.shapes.0.emission.pulse_at", "scene.shapes[0].emission.pulse_at",
      outcomes(2, zero="valid"), fields={"m1": "time.bin"}, contains={"m1": "too narrow for f32 path lengths"})
case("material_unknown", "baseline", SHAPES, [("scene.shapes.0.material", "nope")], 2, "scene.shapes[0].material")

# ---------------------------------------------------------------- scene.emitters
sweep("point_intensity", POINT, "scene.emitters.0.intensity", "scene.emitters[0].intensity", NONNEG)
sweep("point_position", POINT, "scene.emitters.0.position", "scene.emitters[0].position", COORD,
      vec=(1, [0.5, -0.4, 2]))
sweep("point_pulse_at", POINT, "scene.emitters.0.pulse_at", "scene.emitters[0].pulse_at", SIGNED)
sweep("point_spectrum", POINT, "scene.emitters.0.spectrum", "scene.emitters[0].spectrum", NONNEG)
case("point_intensity_1e38_power", "f32", POINT, [("scene.emitters.0.intensity", 1e38)], 2,
     "scene.emitters[0].intensity", "power")
sweep("spot_intensity", SPOT, "scene.emitters.0.intensity", "scene.emitters[0].intensity", NONNEG)
sweep("spot_cone", SPOT, "scene.emitters.0.cone_angle", "scene.emitters[0].cone_angle", ALL2)
# falloff_start in [0, cone_angle].
sweep("spot_falloff_start", SPOT, "scene.emitters.0.falloff_start", "scene.emitters[0].falloff_start", NONNEG)
sweep("spot_position", SPOT, "scene.emitters.0.position", "scene.emitters[0].position", COORD, vec=(0, [0.2, 0.1, 3]))
sweep("spot_direction", SPOT, "scene.emitters.0.direction", "scene.emitters[0].direction", DIRZ, vec=(2, [0, 0, -1]))
sweep("spot_pulse_at", SPOT, "scene.emitters.0.pulse_at", "scene.emitters[0].pulse_at", SIGNED)
sweep("spot_velocity", SPOT, "scene.emitters.0.velocity", "scene.emitters[0].velocity", COORD, vec=(0, [0.5, 0, 0]),
      edits=[("time", {"shutter": [-0.5, 2]})])
sweep("constant_spectrum", SKY, "scene.emitters.0.spectrum", "scene.emitters[0].spectrum", NONNEG)
sweep("directional_irradiance", SKY, "scene.emitters.1.irradiance", "scene.emitters[1].irradiance", NONNEG)
sweep("directional_direction", SKY, "scene.emitters.1.direction", "scene.emitters[1].direction", DIRZ,
      vec=(2, [0, 0, -1]))
sweep("constant_radiance", SKY, "scene.emitters.0.radiance", "scene.emitters[0].radiance", NONNEG)
sweep("envmap_scale", ENV, "scene.emitters.0.scale", "scene.emitters[0].scale", NONNEG)
case("envmap_ok", "baseline", ENV, [], "valid")
case("envmap_huge_header", "crash", ENV, [("scene.emitters.0.path", "../assets/env_huge_header.exr")], 2,
     "scene.emitters[0].path", "200000")
case("envmap_negative_channel", "wrong", ENV, [("scene.emitters.0.path", "../assets/env_negative_channel.exr")], 2,
     "scene.emitters[0].path", "negative")
case("envmap_header_only", "crash", ENV, [("scene.emitters.0.path", "../assets/render_header_only.exr")], 2,
     "scene.emitters[0].path", "truncated")
case("envmap_truncated", "crash", ENV, [("scene.emitters.0.path", "../assets/render_truncated.exr")], 2,
     "scene.emitters[0].path", "cannot read EXR")
case("envmap_dev_urandom", "hang", ENV, [("scene.emitters.0.path", "/dev/urandom")], 2, "scene.emitters[0].path")
case("envmap_not_exr", "baseline", ENV, [("scene.emitters.0.path", "../cases/envmap_ok.json")], 2, "scene.emitters[0].path")
case("emitter_unknown_type", "baseline", POINT, [("scene.emitters.0.type", "laser")], 2, "scene.emitters[0].type")
sweep("moving_light_velocity", MOVING, "scene.emitters.0.velocity", "scene.emitters[0].velocity", COORD,
      vec=(0, [1.5, 0, 0]))

# ---------------------------------------------------------------- spectra
ES = "scene.shapes[0].emission.spectrum"
sweep("spectrum_constant", DISK, "scene.shapes.0.emission.spectrum", ES, NONNEG)
sweep("blackbody_temperature", SPECTRAL, "scene.shapes.0.emission.spectrum.blackbody.temperature", ES, ALL2)
sweep("blackbody_scale", SPECTRAL, "scene.shapes.0.emission.spectrum.blackbody.scale", ES, NONNEG,
      edits=[("scene.shapes.0.emission.spectrum", {"blackbody": {"temperature": 3000, "scale": 1}})])
# A blackbody too faint for f32 (S(λ) is rounded to f32 before anything multiplies it):
# 300 K photons over [380, 400] nm read -50%, 150 K over the visible band 0 for 1.05e-47
# (1.05e-17 at a radiance of 1e30). Refused naming `spectral` below a mean of 2^24 times
# f32's smallest normal number; the blackbody's `scale` brings it back.
FAINT = "too faint for f32"
case("blackbody_300K_photons_380_400", "wrong", SPECTRAL,
     [("scene.shapes.0.emission.spectrum.blackbody.temperature", 300),
      ("spectral", {"band": [380, 400], "sampling": "emitter", "photons": True})], 2, "spectral", FAINT)
case("blackbody_150K_visible", "wrong", SPECTRAL,
     [("scene.shapes.0.emission.spectrum.blackbody.temperature", 150)], 2, "spectral", FAINT)
case("blackbody_150K_visible_radiance_1e30", "wrong", SPECTRAL,
     [("scene.shapes.0.emission.spectrum.blackbody.temperature", 150),
      ("scene.shapes.0.emission.radiance", 1e30)], 2, "spectral", FAINT)
case("blackbody_150K_visible_scaled", "wrong", SPECTRAL,
     [("scene.shapes.0.emission.spectrum", {"blackbody": {"temperature": 150, "scale": 1e30}})], "valid")
case("blackbody_scale_1e37", "f32", SPECTRAL, [("scene.shapes.0.emission.spectrum", {"blackbody": {"temperature": 3000, "scale": 1e37}})],
     2, "scene.shapes[0].emission")
SAMPLED = [("scene.shapes.0.emission.spectrum", {"sampled": {"wavelengths": [380, 780], "values": [1, 1]}})]
sweep("sampled_spectrum_value", SPECTRAL, "scene.shapes.0.emission.spectrum.sampled.values", ES, NONNEG,
      vec=(1, [1, 1]), edits=SAMPLED)
sweep("sampled_spectrum_wavelength", SPECTRAL, "scene.shapes.0.emission.spectrum.sampled.wavelengths", ES, ALL2,
      vec=(0, [380, 780]), edits=SAMPLED)
case("sampled_spectrum_unsorted", "baseline", SPECTRAL,
     [("scene.shapes.0.emission.spectrum", {"sampled": {"wavelengths": [780, 380], "values": [1, 1]}})],
     2, "scene.shapes[0].emission.spectrum")

# ---------------------------------------------------------------- materials and dispersion
sweep("albedo", SHAPES, "scene.materials.white.albedo", "scene.materials.white.albedo", NONNEG)
sweep("eta", BK7, "scene.materials.glass.eta", "scene.materials.glass.eta", ALL2)
sweep("metal_eta", METAL, "scene.materials.metal.eta", "scene.materials.metal.eta", ALL2)
sweep("metal_k", METAL, "scene.materials.metal.k", "scene.materials.metal.k", NONNEG)
SD = "scene.dispersion.glass"
BK7_B = [1.03961212, 0.231792344, 1.01046945]
BK7_C = [0.00600069867, 0.0200179144, 103.560653]
# A coefficient of -1 or 0 still gives an index within the dielectric's bounds over the band.
sweep("sellmeier_b", BK7, "scene.dispersion.glass.eta.sellmeier.b", SD + ".eta.sellmeier.b", SIGNED, vec=(0, BK7_B))
sweep("sellmeier_c", BK7, "scene.dispersion.glass.eta.sellmeier.c", SD + ".eta.sellmeier.c", SIGNED, vec=(2, BK7_C))
sweep("dispersion_eta", BK7, "scene.dispersion.glass.eta", SD + ".eta", ALL2)
CAUCHY = [("scene.dispersion.glass.eta", {"cauchy": {"a": 1.5046, "b": 0.0042, "c": 0}})]
# A Cauchy index that leaves the dielectric's range names `eta`; one that is not positive
# over the band names `eta.cauchy`; a number that is no f32 names its coefficient.
sweep("cauchy_a", BK7, "scene.dispersion.glass.eta.cauchy.a", SD + ".eta", ALL2, edits=CAUCHY)
sweep("cauchy_b", BK7, "scene.dispersion.glass.eta.cauchy.b", SD + ".eta.cauchy", NONNEG, edits=CAUCHY)
sweep("cauchy_c", BK7, "scene.dispersion.glass.eta.cauchy.c", SD + ".eta.cauchy", NONNEG, edits=CAUCHY)
case("sellmeier_pole_in_band", "wrong", BK7, [("spectral.band", [400, 20000])], 2, SD + ".eta.sellmeier.c", "pole")
case("sellmeier_wavelength_at_pole", "wrong", BK7, [("spectral", {"wavelength": 10176.5})], 2,
     SD + ".eta", "over [10176.5, 10177.5] nm")
# The scene's own check used [360, 830] nm whatever the case measured: a pole at 600 nm
# refused [400, 500] nm and λ = 500 nm. Checked over the measured band; inside it, refused.
POLE600 = [("scene.dispersion.glass.eta", {"sellmeier": {"b": [0.1, 0, 0], "c": [0.36, 0, 0]}})]
case("sellmeier_pole_beyond_band", "wrong", BK7, POLE600 + [("spectral.band", [400, 500])], "valid")
case("sellmeier_pole_beyond_wavelength", "wrong", BK7, POLE600 + [("spectral", {"wavelength": 500})], "valid")
case("sellmeier_pole_600_in_band", "wrong", BK7, POLE600 + [("spectral.band", [500, 700])], 2,
     SD + ".eta.sellmeier.c", "pole")
case("conductor_k_via_dispersion", "wrong", METAL, [("scene.dispersion.metal.k", 1000)], 2, "scene.dispersion.metal.k", "100")
sweep("conductor_k_via_dispersion", METAL, "scene.dispersion.metal.k", "scene.dispersion.metal.k", NONNEG)
case("conductor_k_via_dispersion_ok", "baseline", METAL, [], "valid")

# ---------------------------------------------------------------- spectral and time sections
case("band_too_narrow", "wrong", SPECTRAL, [("spectral.band", [500, 500.00000001])], 2, "spectral.band", "narrow")
case("band_1e39", "f32", SPECTRAL, [("spectral.band", [500, 1e39])], 2, "spectral.band")
sweep("band", SPECTRAL, "spectral.band", "spectral.band", ALL2, vec=(0, [380, 780]))
sweep("response_value", SPECTRAL, "spectral.response.sampled.values", "spectral.response", NONNEG, vec=(1, [1, 1]),
      edits=[("spectral.response", {"sampled": {"wavelengths": [380, 780], "values": [1, 1]}})])
# A response or an emitter's spectrum of 3e38 over 100 nm: each value fits f32, the
# sample's weight R·width (or the spectrum times it) does not; every sample came out
# non-finite ("an engine bug"). Refused up front naming `spectral`.
case("response_times_band_overflows", "wrong", SPECTRAL, [("spectral.band", [400, 500]),
     ("spectral.response", {"sampled": {"wavelengths": [400, 500], "values": [3e38, 3e38]}})],
     2, "spectral", "overflows f32")
case("spectrum_times_band_overflows", "wrong", SPECTRAL, [("spectral.band", [400, 500]),
     ("scene.shapes.0.emission.spectrum", {"sampled": {"wavelengths": [400, 500], "values": [3e38, 3e38]}})],
     2, "spectral", "overflows f32")
# The same with `emitter` sampling's table: a spike between the three points each cell was
# looked at got only the defensive share of the density, 1/10 of a uniform draw's, so 3e36
# over 100 nm gave non-finite samples (exit 1) past a bound that assumed a uniform draw.
# Each cell now takes the spectrum's exact maximum over it: 3e36 runs, finite; 3e37 is
# refused by the bound, which allows the table's least density, 0.9 of the target's.
# The spike was 0.02 nm wide over [400, 500] nm; table pieces now obey the band rule
# (at least 1e-4·λ), so it is 0.1 nm wide over [400, 800] nm (cells 0.39 nm, looked at
# 0.195 nm apart: still between the points), its peak a quarter of the old one.
SPIKE = {"sampled": {"wavelengths": [400, 400.5, 401, 401.5, 450.05, 450.1, 450.15],
                     "values": [0, 1e30, 1e30, 0, 0, 7.5e35, 0]}}
for name, sampling, peak, outcome in [("spectrum_spike_emitter_sampling", "emitter", 7.5e35, "valid"),
                                      ("spectrum_spike_uniform_sampling", "uniform", 7.5e35, "valid"),
                                      ("spectrum_spike_emitter_sampling_overflows", "emitter", 7.5e36, 2)]:
    spike = copy.deepcopy(SPIKE)
    spike["sampled"]["values"][5] = peak
    case(name, "wrong", SPECTRAL,
         [("spectral", {"band": [400, 800], "sampling": sampling, "hero": False}),
          ("scene.shapes.0.emission.spectrum", spike)],
         outcome, "spectral" if outcome == 2 else None, "emitter` sampling over n emitters" if outcome == 2 else None)
# A table's piece narrower than f32 wavelengths resolve: a spike [499.9995, 500, 500.0005]
# of peak 1e6 integrated to 488.6 (the f32 table's 488.28) for 500. Each piece is now at
# least 1e-4·λ wide, as a band is; 0.06 nm at 500 nm runs.
for name, w, outcome in [("spectrum_piece_too_narrow", [499.9995, 500, 500.0005], 2),
                         ("spectrum_piece_narrower_still", [499.99995, 500, 500.00005], 2),
                         ("spectrum_piece_at_the_band_rule", [499.94, 500, 500.06], "valid")]:
    case(name, "wrong", SPECTRAL,
         [("spectral", {"band": [400, 600], "sampling": "emitter"}),
          ("scene.shapes.0.emission.spectrum", {"sampled": {"wavelengths": w, "values": [0, 1e6, 0]}})],
         outcome, "scene.shapes[0].emission.spectrum.sampled.wavelengths" if outcome == 2 else None,
         "too narrow for f32 wavelengths" if outcome == 2 else None)
case("response_piece_too_narrow", "wrong", SPECTRAL,
     [("spectral.response", {"sampled": {"wavelengths": [380, 550, 550.01, 780], "values": [1, 1, 2, 2]}})],
     2, "spectral.response.sampled.wavelengths", "too narrow for f32 wavelengths")
# A rough dielectric with η at or near 1: every sample was lost at η = 1 (a delta
# transmission) and, within 1e-5, albedos read up to 33% low or 0; at 1e-4 (taken until
# session 52) GGX at α = 1 read 1.4e-4 low at 2^22 samples. Refused, naming `eta`.
for name, alpha, eta in [("rough_dielectric_eta_1", 0.3, 1), ("rough_dielectric_eta_near_1", 0.3, 1.00001),
                         ("rough_dielectric_eta_1e-4_from_1", 1, 1.0001),
                         ("rough_dielectric_eta_1e-4_below_1", 1, 0.9999)]:
    case(name, "wrong", ALBEDO, [("measure.albedo.bsdf", {"type": "rough_dielectric", "alpha": alpha, "eta": eta})],
         2, "measure.albedo.bsdf.eta", "from 1")
# At 1e-3 from 1 it is taken (and agrees with the oracle: README "A rough dielectric
# barely refracting").
for name, eta in [("rough_dielectric_eta_1e-3_from_1", 1.001), ("rough_dielectric_eta_1e-3_below_1", 0.999)]:
    case(name, "wrong", ALBEDO, [("measure.albedo.bsdf", {"type": "rough_dielectric", "alpha": 1, "eta": eta})], "valid")
sweep("wavelength", SPECTRAL, "spectral.wavelength", "spectral.wavelength", ALL2,
      edits=[("spectral", {"wavelength": 550})])
# The shutter's end: -1 puts it before its start [-0.5, ...].
sweep("shutter", MOVING, "time.shutter", "time.shutter", outcomes(2, zero="valid"), vec=(1, [-0.5, 2]))
case("shutter_reversed", "baseline", MOVING, [("time.shutter", [2, -0.5])], 2, "time.shutter")
# Time is sampled from the shutter's start: 10 ms at t = 1e6 s is resolved (once refused
# as "too short" in f32 seconds); a length that is not a normal f32 is refused.
case("shutter_far_10ms", "wrong", MOVING, [("time.shutter", [1e6, 1e6 + 0.01]),
     ("scene.emitters.0.position", [-1.5e6, 0, 2])], "valid")
case("shutter_length_subnormal", "f32", MOVING, [("time.shutter", [1e-30, 1e-30 + 1e-39])], 2,
     "time.shutter", "not a normal f32")
case("shutter_length_overflow", "f32", MOVING, [("time.shutter", [-3e38, 3e38]),
     ("scene.emitters.0.velocity", [1e-30, 0, 0])], 2, "time.shutter", "not a normal f32")
# A pulsed emitter that moves was sampled where it is at the shutter's time, not where it
# flashed (0.030 where the flash at x = 0 gives 0.75 or nothing): pulse and motion refused.
case("pulse_while_moving", "wrong", MOVING, [("scene.emitters.0.pulse_at", 0)], 2, "time.shutter",
     "a pulse and motion together")
sweep("bin", PULSE, "time.bin", "time.bin", SIGNED, vec=(0, PULSE["time"]["bin"]))
# Arrivals are binned by the f32 path length ℓ (a step of 2^-23·ℓ, 0.4 fs at 1 m): 10 fs
# bins after the first arrival at 1 m read z = +9..+13 and -9. A bin is now at least 1e-4
# of the time since the pulse; 0.34 ps bins there run.
H = 3.3356409519815204e-09
case("bins_10fs_at_1m", "wrong", PULSE, [("time.bin", DELETE), ("scene.shapes.0.geometry.radius", 0.006928244799370184),
     ("time.bins", [H + k * 1.0006922885856e-14 for k in range(9)])], 2, "time.bins", "too narrow for f32 path lengths")
case("bin_10fs_at_1m", "wrong", PULSE, [("time.bin", [H, H + 1e-14])], 2, "time.bin", "too narrow for f32 path lengths")
case("bins_at_the_f32_length_rule", "wrong", PULSE, [("time.bin", DELETE), ("scene.shapes.0.geometry.radius", 0.05),
     ("time.bins", [H + k * 3.4e-13 for k in range(9)])], "valid")
sweep("bins", PULSE, "time.bins", "time.bins", SIGNED, vec=(0, [0, 4e-9, 5e-9]), edits=[("time.bin", DELETE)])

# ---------------------------------------------------------------- measure
sweep("measure_at", DISK, "measure.irradiance.at", "measure.irradiance.at", COORD, vec=(0, [0, 0, 0]),
      fields={"str": "measure.irradiance.at"})
case("measure_normal_tiny", "unclear", DISK, [("measure.irradiance.normal", [0, 0, 1e-320])], 2, "measure.irradiance.normal",
     "too small to normalise")
sweep("measure_normal", DISK, "measure.irradiance.normal", "measure.irradiance.normal", DIRZ, vec=(2, [0, 0, 1]),
      fields={"str": "measure.irradiance.normal"})
sweep("radiance_at", SPECTRAL, "measure.radiance.at", "measure.radiance.at", COORD, vec=(2, [0, 0, 0]),
      fields={"str": "measure.radiance.at"})
sweep("radiance_direction", SPECTRAL, "measure.radiance.direction", "measure.radiance.direction", DIRZ, vec=(2, [0, 0, 1]),
      fields={"str": "measure.radiance.direction"})
# The other measurements' fields: a viewpoint, a normal or direction, a shape or emitter index.
TRI = {"geometry": {"type": "triangle", "vertices": [[0.3, -0.4, 1.2], [1.5, 0.2, 1], [-0.2, 0.9, 1.6]]}}
SOLID = {"name": "solid angle", "teaches": "Van Oosterom–Strackee", "scene": {"shapes": [TRI]},
         "measure": {"solid_angle": {"from": [0, 0, 0], "shape": 0}}, "estimators": ["area"]}
PSA = dict(SOLID, measure={"projected_solid_angle": {"from": [0, 0, 0], "normal": [0, 0, 1], "shape": 0}})
INTENSITY = {"name": "intensity", "teaches": "Lambert's cosine law",
             "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1},
                                   "emission": {"radiance": 1}}]},
             "measure": {"intensity": {"shape": 0, "direction": [0, 0, 1]}}, "estimators": ["area"]}
sweep("solid_angle_from", SOLID, "measure.solid_angle.from", "measure.solid_angle.from", COORD, vec=(0, [0, 0, 0]),
      fields={"str": "measure.solid_angle.from"})
sweep("solid_angle_shape", SOLID, "measure.solid_angle.shape", "measure.solid_angle.shape",
      outcomes(2, zero="valid"))
sweep("psa_from", PSA, "measure.projected_solid_angle.from", "measure.projected_solid_angle.from", COORD, vec=(1, [0, 0, 0]),
      fields={"str": "measure.projected_solid_angle.from"})
sweep("psa_normal", PSA, "measure.projected_solid_angle.normal", "measure.projected_solid_angle.normal", DIRZ, vec=(2, [0, 0, 1]),
      fields={"str": "measure.projected_solid_angle.normal"})
sweep("psa_shape", PSA, "measure.projected_solid_angle.shape", "measure.projected_solid_angle.shape",
      outcomes(2, zero="valid"))
sweep("intensity_direction", INTENSITY, "measure.intensity.direction", "measure.intensity.direction", DIRZ,
      vec=(2, [0, 0, 1]), fields={"str": "measure.intensity.direction"})
sweep("intensity_shape", INTENSITY, "measure.intensity.shape", "measure.intensity.shape", outcomes(2, zero="valid"))
sweep("albedo_theta", ALBEDO, "measure.albedo.theta_degrees", "measure.albedo.theta_degrees", NONNEG)
sweep("albedo_phi", ALBEDO, "measure.albedo.phi_degrees", "measure.albedo.phi_degrees", SIGNED)
# Every parameter of every BSDF, in the albedo measurement (the same code reads
# `scene.materials`: see albedo, eta, metal_eta, metal_k above). Albedos and k may be 0;
# roughness, indices and alpha may not.
BSDFS = [
    ("lambertian", {"type": "lambertian", "albedo": 0.5}, {"albedo": NONNEG}),
    ("oren_nayar", {"type": "oren_nayar", "albedo": 0.8, "sigma": 0.5}, {"albedo": NONNEG, "sigma": NONNEG}),
    ("conductor", {"type": "conductor", "eta": 0.2, "k": 3.9}, {"eta": ALL2, "k": NONNEG}),
    ("dielectric", {"type": "dielectric", "eta": 1.5}, {"eta": ALL2}),
    ("rough_dielectric", {"type": "rough_dielectric", "alpha": 0.3, "eta": 1.5}, {"alpha": ALL2, "eta": ALL2}),
    ("plastic", {"type": "plastic", "albedo": 0.5, "eta": 1.5}, {"albedo": NONNEG, "eta": ALL2}),
]
for kind, bsdf, params in BSDFS:
    for param, outs in params.items():
        sweep("bsdf_%s_%s" % (kind, param), ALBEDO, "measure.albedo.bsdf." + param, "measure.albedo.bsdf." + param,
              outs, edits=[("measure.albedo.bsdf", bsdf)])
# The rough conductor of ALBEDO, and the classic Oren–Nayar of ONC below.
for param, outs in [("alpha", ALL2), ("eta", ALL2), ("k", NONNEG)]:
    sweep("albedo_bsdf_" + param, ALBEDO, "measure.albedo.bsdf." + param, "measure.albedo.bsdf." + param, outs)
# ---------------------------------------------------------------- issue 17: F ≡ 1, Oren–Nayar classic, microfacet integrals
WHITE = dict(ALBEDO, measure={"albedo": {"bsdf": {"type": "rough_conductor", "alpha": 0.3, "fresnel": "none"},
                                         "theta_degrees": 60}})
case("white_valid", "baseline", WHITE, [], "valid")
case("white_fresnel_off", "baseline", WHITE, [("measure.albedo.bsdf.fresnel", "off")], 2, "measure.albedo.bsdf.fresnel", "`fresnel`")
case("white_fresnel_number", "baseline", WHITE, [("measure.albedo.bsdf.fresnel", 1)], 2, "measure.albedo.bsdf.fresnel", "`fresnel`")
case("white_with_eta", "unclear", WHITE, [("measure.albedo.bsdf.eta", 1.5)], 2, "measure.albedo.bsdf.eta", "must be absent")
case("white_with_k", "unclear", WHITE, [("measure.albedo.bsdf.k", 3.9)], 2, "measure.albedo.bsdf.k", "must be absent")
case("conductor_without_eta", "unclear", ALBEDO, [("measure.albedo.bsdf.eta", DELETE)], 2, "measure.albedo.bsdf.eta", "is required")
case("conductor_without_k", "unclear", ALBEDO, [("measure.albedo.bsdf.k", DELETE)], 2, "measure.albedo.bsdf.k", "is required")
case("white_material_fresnel_off", "baseline", SHAPES, [("scene.materials.white", {"type": "rough_conductor", "alpha": 0.3, "fresnel": "off"})],
     2, "scene.materials.white.fresnel", "`fresnel`")
ONC = dict(ALBEDO, measure={"albedo": {"bsdf": {"type": "oren_nayar_classic", "albedo": 0.8, "sigma": 0.3},
                                       "theta_degrees": 60}})
case("on_classic_valid", "baseline", ONC, [], "valid")
# A subnormal σ or albedo was read straight into f32 and ran (exit 0): refused now, as
# everywhere else, by the same f32 check.
OB = "measure.albedo.bsdf."
sweep("on_classic_sigma", ONC, OB + "sigma", OB + "sigma", NONNEG,
      contains={"m1": "must", "sub": "underflows f32", "sub64": "underflows f32", "e39": "overflows f32",
                "str": "expected f64"})
case("on_classic_sigma_two", "baseline", ONC, [(OB + "sigma", 2.0)], 2, OB + "sigma", "must")
sweep("on_classic_albedo", ONC, OB + "albedo", OB + "albedo", NONNEG,
      contains={"m1": "must lie in [0, 1]", "sub": "underflows f32"})
MF = {"name": "microfacet", "teaches": "projected area",
      "measure": {"microfacet": {"distribution": "ggx", "alpha": 0.3, "theta_degrees": 60, "integral": "projected_area"}},
      "reference": {"closed_form": "microfacet_projected_area", "distribution": "ggx", "alpha": 0.3, "cos_theta": 0.5},
      "estimators": ["uniform"]}
case("microfacet_valid", "baseline", MF, [], "valid")
case("microfacet_grazing_90_valid", "baseline", MF, [("measure.microfacet.theta_degrees", 90), ("reference.cos_theta", 0)], "valid")
sweep("microfacet_alpha", MF, "measure.microfacet.alpha", "measure.microfacet.alpha", ALL2)
case("microfacet_alpha_two", "baseline", MF, [("measure.microfacet.alpha", 2)], 2, "measure.microfacet.alpha")
sweep("microfacet_theta", MF, "measure.microfacet.theta_degrees", "measure.microfacet.theta_degrees", NONNEG)
# A reference's parameters go to the f64 closed forms of lightproof-analytic, not to the
# f32 engine: a value inside the closed form's domain runs (a wrong reference fails its
# verdict, exit 1), one outside it, or one whose value is not finite, is refused.
sweep("microfacet_reference_alpha", MF, "reference.alpha", "reference.alpha", ALL2)
sweep("microfacet_reference_cos_theta", MF, "reference.cos_theta", "reference.cos_theta",
      outcomes(2, zero="valid", sub="valid"), fields={"sub64": "reference"}, contains={"sub64": "non-finite result"})
case("microfacet_theta_missing", "wrong", MF, [("measure.microfacet.theta_degrees", DELETE)], 2,
     "measure.microfacet.theta_degrees", "missing")
case("microfacet_normalisation_theta", "wrong", MF, [("measure.microfacet.integral", "normalisation"),
     ("reference", {"closed_form": "microfacet_normalisation", "distribution": "ggx", "alpha": 0.3})], 2,
     "measure.microfacet.theta_degrees", "does not depend on")
case("microfacet_normalisation_valid", "baseline", MF, [("measure.microfacet.integral", "normalisation"),
     ("measure.microfacet.theta_degrees", DELETE),
     ("reference", {"closed_form": "microfacet_normalisation", "distribution": "ggx", "alpha": 0.3})], "valid")
case("microfacet_alpha_1e-3", "wrong", MF, [("measure.microfacet.alpha", 1e-3), ("reference.alpha", 1e-3)], 2,
     "measure.microfacet.alpha", "[0.01, 1]")
case("microfacet_alpha_0_01_valid", "baseline", MF, [("measure.microfacet.alpha", 0.01), ("reference.alpha", 0.01)], "valid")
case("microfacet_theta_91", "baseline", MF, [("measure.microfacet.theta_degrees", 91)], 2, "measure.microfacet.theta_degrees")
case("microfacet_visible_90", "unclear", MF, [("measure.microfacet.integral", "visible"), ("measure.microfacet.theta_degrees", 90),
     ("reference", DELETE)], 2, "measure.microfacet.theta_degrees", "cos")
case("microfacet_distribution_phong", "baseline", MF, [("measure.microfacet.distribution", "phong")], 2, "measure.microfacet.distribution")
case("microfacet_integral_area", "baseline", MF, [("measure.microfacet.integral", "area")], 2, "measure.microfacet.integral")
case("microfacet_integral_missing", "baseline", MF, [("measure.microfacet.integral", DELETE)], 2, "integral")
case("microfacet_estimator_bsdf", "baseline", MF, [("estimators", ["bsdf"])], 2, "estimators[0]")
case("microfacet_reference_distribution", "baseline", MF, [("reference.distribution", "phong")], 2, "reference.distribution", "`distribution`")
case("microfacet_reference_masking", "baseline", MF, [("reference", {"closed_form": "microfacet_white_albedo", "distribution": "ggx",
     "masking": "separable", "alpha": 0.3, "cos_theta": 0.5})], 2, "reference.masking", "`masking`")
case("microfacet_reference_alpha", "baseline", MF, [("reference.alpha", 0)], 2, "reference.alpha", "`alpha`")
sweep("segments", CHORD, "measure.mean_path_length.segments", "measure.mean_path_length.segments", ALL2)
sweep("chord_shape", CHORD, "measure.mean_path_length.shape", "measure.mean_path_length.shape",
      outcomes(2, zero="valid"))
case("segments_huge", "hang", CHORD, [("measure.mean_path_length.segments", 4294967295)], 2,
     "measure.mean_path_length.segments")
case("measure_shape_missing", "baseline", CHORD, [("measure.mean_path_length.shape", 7)], 2, "measure.mean_path_length.shape")
sweep("power_shape", POWER, "measure.power.shape", "measure.power.shape", outcomes(2, zero="valid"))
case("power_ok", "baseline", POWER, [], "valid")
case("measure_unknown", "baseline", DISK, [("measure", {"glow": {}})], 2, "measure")
case("measure_missing", "baseline", DISK, [("measure", DELETE)], 2, "measure")

# ---------------------------------------------------------------- reference, samples, estimators, top level
# A rough conductor's albedo reference at extreme indices (fuzzing with a seed of 101 found
# η = 1e308: NaN Fresnel factors kept the oracle's nested quadrature bisecting for over
# ten minutes; now F ≈ 1 there, and a non-finite integrand stops the quadrature at once).
CONDUCTOR_REF = dict(ALBEDO, reference={"closed_form": "microfacet_conductor_albedo", "distribution": "ggx",
                                        "masking": "height_correlated", "alpha": 0.3, "cos_theta": 0.5,
                                        "eta": 0.2, "k": 3.9})
sweep("conductor_reference_eta", CONDUCTOR_REF, "reference.eta", "reference.eta", outcomes("valid", m1=2, zero=2, str=2))
sweep("conductor_reference_k", CONDUCTOR_REF, "reference.k", "reference.k", outcomes("valid", m1=2, str=2))

# A rough dielectric's albedo reference: eta within [0.1, 10], where its quadrature is
# validated (fuzzing with a seed of 1007 found eta = 1.5e12, which took it minutes).
DIELECTRIC_REF = dict(ALBEDO, reference={"closed_form": "microfacet_dielectric_albedo", "distribution": "ggx",
                                         "masking": "height_correlated", "alpha": 0.3, "cos_theta": 0.5,
                                         "eta": 1.5})
sweep("dielectric_reference_eta", DIELECTRIC_REF, "reference.eta", "reference.eta", outcomes(2))
case("dielectric_reference_eta_1.5e12", "hang", DIELECTRIC_REF, [("reference.eta", 1.5e12)], 2, "reference.eta",
     "[0.1, 10]")
case("dielectric_reference_eta_10_valid", "baseline", DIELECTRIC_REF, [("reference.eta", 10)], "valid")

# As for microfacet_reference_* above: the closed form's domain, in f64.
sweep("reference_scale", REF, "reference.scale", "reference.scale", outcomes("valid", m1=2, zero=2, str=2))
# A disk of radius 1e308 (with height 2 or 1e308): E = pi L/(1 + (h/R)^2), pi and pi/2; the
# oracle once formed R^2 and refused them as non-finite, now it computes them (the
# estimate then fails against the scene's unit disk: exit 1, a valid run).
sweep("reference_radius", REF, "reference.radius", "reference.radius", outcomes("valid", m1=2, zero=2, str=2))
sweep("reference_height", REF, "reference.height", "reference.height", outcomes("valid", m1=2, zero=2, str=2))
sweep("reference_radiance", REF, "reference.radiance", "reference.radiance", outcomes("valid", m1=2, e308=2, str=2),
      fields={"e308": "reference"}, contains={"e308": "non-finite result"})
case("reference_radius_height_e308", "f32", REF, [("reference.radius", 1e308), ("reference.height", 1e308)], "valid")
case("reference_unknown", "baseline", REF, [("reference.closed_form", "nope")], 2, "reference.closed_form")
case("samples_huge", "hang", DISK, [("samples", 18446744073709551615)], 2, "samples", "2^40")
sweep("samples", DISK, "samples", "samples", ALL2)
case("estimators_empty", "baseline", DISK, [("estimators", [])], 2, "estimators")
case("estimator_unknown", "baseline", DISK, [("estimators", ["magic"])], 2, "estimators")
case("estimator_wrong_measure", "baseline", DISK, [("estimators", ["area"])], 2, "estimators[0]")
# Listed twice: one series run twice with one seed, counted twice by the Šidák correction.
case("estimators_twice", "wrong", DISK, [("estimators", ["light", "mis", "light"])], 2, "estimators[2]",
     "`light` is listed twice")
case("samplers_twice", "wrong", dict(DISK, samplers=["sobol", "sobol"]), [], 2, "samplers[1]",
     "`sobol` is listed twice")
# An empty list ran the default sampler without a word, where an empty estimator list is refused.
case("samplers_empty", "unclear", dict(DISK, samplers=[]), [], 2, "samplers", "at least one sampler")
case("unknown_field", "baseline", DISK, [("colour", 1)], 2, "colour")
# A text that ends, or breaks, before a key is read: the file as a whole is at fault, so
# the message leaves the field out (`FILE: REASON`; it once read `FILE: ?: REASON`); a
# text that ends inside a value names the field whose value it is.
NO_FIELD = ": ?:"
case("malformed_json", "baseline", DISK, [], 2, "name", "malformed_json.json: name: EOF while parsing a value",
     raw='{ "name": ', absent=NO_FIELD)
case("truncated_object", "unclear", DISK, [], 2, None, "truncated_object.json: EOF while parsing an object",
     raw='{', absent=NO_FIELD)
case("truncated_after_comma", "unclear", DISK, [], 2, None, "truncated_after_comma.json: EOF while parsing a value",
     raw='{"name": "a", ', absent=NO_FIELD)
case("missing_comma", "unclear", DISK, [], 2, None, "missing_comma.json: expected `,` or `}`",
     raw='{"name": "a" "teaches": "t"}', absent=NO_FIELD)
# Text after the document: the file is not one JSON value, and what follows the first
# value was once ignored (exit 0). The file as a whole is at fault.
case("trailing_object", "wrong", DISK, [], 2, None, "trailing_object.json: trailing characters",
     raw=json.dumps(DISK) + '\n{"samples": 1}', absent=NO_FIELD)
case("trailing_garbage", "wrong", DISK, [], 2, None, "trailing_garbage.json: trailing characters",
     raw=json.dumps(DISK) + " xyz", absent=NO_FIELD)
case("trailing_braces", "wrong", DISK, [], 2, None, "trailing_braces.json: trailing characters",
     raw=json.dumps(DISK) + "}}}", absent=NO_FIELD)
case("truncated_nested", "baseline", DISK, [], 2, "truncated_nested.json: scene.shapes[0].geometry: EOF",
     raw='{"scene": {"shapes": [{"geometry": ', absent="?")
case("not_an_object", "baseline", DISK, [], 2, "invalid type", raw='[1, 2, 3]')
case("deep_nesting", "baseline", DISK, [], 2, "deep_nesting.json", raw="[" * 100000 + "]" * 100000)
case("valid_disk", "baseline", DISK, [], "valid")
case("valid_spectral", "baseline", SPECTRAL, [], "valid")
case("valid_pulse", "baseline", PULSE, [], "valid")
# Valid extremes whose light density overflows f32 (found by fuzz_cases with a
# non-finite counter): every sample was NaN (exit 1, estimate 0). The emitter subtends
# less than 1/f32::MAX sr per unit density there, so no sample: a finite estimate of 0
# with no non-finite sample (hostile.rs checks both for every valid estimate).
def light_far(name, shapes, at, normal):
    case(name, "wrong", dict(DISK, scene={"shapes": shapes}, estimators=["light", "mis"],
                             measure={"irradiance": {"at": at, "normal": normal}}), [], "valid")
ANNULUS = {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 1,
                        "inner_radius": 0.99}, "emission": {"radiance": 1}}
light_far("far_receiver_annulus", [ANNULUS], [1e18, 0, 0], [0, 0, 1])
light_far("far_tiny_sphere", [{"geometry": {"type": "sphere", "center": [0.5, 0.3, 1e18], "radius": 1e-15},
                               "emission": {"radiance": 1}}], [0, 0, 0], [0, 0, 1])
light_far("far_small_sphere", [{"geometry": {"type": "sphere", "center": [0.5, 0.3, 9e15], "radius": 1e-8},
                                "emission": {"radiance": 1}}], [0, 0, 0], [0, 0, 1])
light_far("sliver_triangle_far_vertex",
          [{"geometry": {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [1e18, 1, 0]]},
            "emission": {"radiance": 1, "two_sided": True}}],
          [1.0, 1.0, 1e-7], [-0.7071067811865476, -0.7071067811865476, 0])
# Counting photons over [10 nm, 1 cm] multiplies a strength by up to λ/(hc) = 5e22 per
# joule and the band width: at radiance 1e18 every sample was +inf (found by fuzz_cases at
# seed 5); the bound refuses it, naming spectral.photons, and 1e6 runs.
PHOTONS = {"name": "photons", "teaches": "N = int B lambda/(hc) dlambda",
           "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 4},
                                 "emission": {"radiance": 1e18, "spectrum": {"blackbody": {"temperature": 2000}}}}]},
           "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
           "spectral": {"band": [10, 1e7], "photons": True, "sampling": "emitter"}, "estimators": ["mis"]}
case("photons_overflow", "wrong", PHOTONS, [], 2, "spectral.photons", "overflows f32")
case("photons_within_f32", "wrong", PHOTONS, [("scene.shapes.0.emission.radiance", 1e6)], "valid")
case("huge_receiver_disk", "wrong",
     dict(DISK, estimators=["light", "mis"], measure={"flux": {"shape": 1, "view_factor": True}},
          scene={"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 1},
                             "emission": {"radiance": 1}},
                            {"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1],
                                          "radius": 9007199254740993}}]}), [], "valid")
# A histogram of at most 1024 bins (1025 edges): 1024 runs, 1025 is refused.
EDGES = lambda n: [i * 1e-10 for i in range(n + 1)]
case("bins_1024", "baseline", PULSE, [("time.bin", DELETE), ("time.bins", EDGES(1024))], "valid")
case("bins_1025", "hang", PULSE, [("time.bin", DELETE), ("time.bins", EDGES(1025))], 2, "time.bins", "1024")
case("valid_moving", "baseline", MOVING, [], "valid")
case("valid_bk7", "baseline", BK7, [], "valid")
case("valid_albedo", "baseline", ALBEDO, [], "valid")
case("valid_shapes_tiny_coordinates", "baseline", SHAPES, [("scene.shapes.1.geometry.corner", [-1, -1, 4 + 1e-300])], "valid")
case("valid_far_point_light", "baseline", POINT, [("scene.emitters.0.position", [1e17, 0, 1e17]),
                                                   ("scene.emitters.0.intensity", 1e30)], "valid")

# ---------------------------------------------------------------- partial shapes, flux, max_depth (issue 17)
ANNULUS = dict(DISK, scene={"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1],
                                                     "radius": 1, "inner_radius": 0.5}, "emission": {"radiance": 1}}]})
CAP = {
    "name": "emissive cap", "teaches": "E = pi L sin^2 theta_max at the centre",
    "scene": {"shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1, "theta_max": 60,
                                       "axis": [0, 0, 1]}, "flip_normals": True, "emission": {"radiance": 1}}]},
    "measure": {"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}},
    "estimators": ["light", "mis"]}
FLUX = {
    "name": "view factor", "teaches": "F = Phi / (pi L A)",
    "scene": {"shapes": [{"geometry": {"type": "rectangle", "corner": [0, 0, 1], "edge_u": [0, 1, 0], "edge_v": [1, 0, 0]},
                          "emission": {"radiance": 1}},
                         {"geometry": {"type": "rectangle", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0]}}]},
    "measure": {"flux": {"shape": 1, "view_factor": True}},
    "estimators": ["light", "mis"]}
DEPTH = {
    "name": "furnace bounces", "teaches": "L_k = Le (1 - rho^(k+1)) / (1 - rho)",
    "scene": {"materials": {"grey": {"type": "lambertian", "albedo": 0.5}},
              "shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1}, "material": "grey",
                          "flip_normals": True, "emission": {"radiance": 1}}]},
    "measure": {"radiance": {"at": [0.2, -0.1, 0.3], "direction": [0.3, 0.5, -0.8]}},
    "max_depth": 2,
    "estimators": ["mis"]}
IR = "scene.shapes[0].geometry.inner_radius"
sweep("annulus_inner_radius", ANNULUS, "scene.shapes.0.geometry.inner_radius", IR, NONNEG)
case("annulus_inner_equals_outer", "wrong", ANNULUS, [("scene.shapes.0.geometry.inner_radius", 1)], 2, IR)
case("annulus_inner_above_outer", "wrong", ANNULUS, [("scene.shapes.0.geometry.inner_radius", 1.5)], 2, IR)
case("annulus_inner_rounds_to_outer", "f32", ANNULUS, [("scene.shapes.0.geometry.inner_radius", 1 - 1e-12)], 2, IR)
case("annulus_valid", "baseline", ANNULUS, [], "valid")
TM = "scene.shapes[0].geometry.theta_max"
sweep("cap_theta_max", CAP, "scene.shapes.0.geometry.theta_max", TM, ALL2)
case("cap_theta_max_180_5", "wrong", CAP, [("scene.shapes.0.geometry.theta_max", 180.5)], 2, TM)
case("cap_theta_max_720", "wrong", CAP, [("scene.shapes.0.geometry.theta_max", 720)], 2, TM)
case("cap_theta_max_1e-30", "f32", CAP, [("scene.shapes.0.geometry.theta_max", 1e-30)], 2, TM)
case("cap_theta_max_180", "baseline", CAP, [("scene.shapes.0.geometry.theta_max", 180)], "valid")
sweep("cap_axis", CAP, "scene.shapes.0.geometry.axis", "scene.shapes[0].geometry.axis", DIRZ, vec=(2, [0, 0, 1]))
case("cap_axis_without_theta_max", "unclear", CAP, [("scene.shapes.0.geometry.theta_max", DELETE)], 2,
     "scene.shapes[0].geometry.axis")
case("cap_valid", "baseline", CAP, [], "valid")
case("max_depth_huge", "hang", DEPTH, [("max_depth", 4294967295)], 2, "max_depth")
case("max_depth_65537", "hang", DEPTH, [("max_depth", 65537)], 2, "max_depth")
case("max_depth_fraction", "baseline", DEPTH, [("max_depth", 1.5)], 2, "max_depth")
sweep("max_depth", DEPTH, "max_depth", "max_depth", ALL2)
case("max_depth_on_power", "wrong", POWER, [("max_depth", 2)], 2, "max_depth")
case("max_depth_irradiance_valid", "baseline", dict(DISK, max_depth=1), [], "valid")
case("max_depth_valid", "baseline", DEPTH, [], "valid")
case("flux_shape_missing", "baseline", FLUX, [("measure.flux.shape", 7)], 2, "measure.flux.shape")
# Shape 0 is the emitter itself.
sweep("flux_shape", FLUX, "measure.flux.shape", "measure.flux.shape", ALL2, fields={"zero": "measure.flux.view_factor"})
case("flux_receiver_degenerate", "wrong", FLUX, [("scene.shapes.1.geometry.edge_v", [2, 0, 0])], 2,
     "scene.shapes[1].geometry")
case("flux_receiver_is_emitter", "wrong", FLUX, [("measure.flux.shape", 0)], 2, "measure.flux.view_factor")
# A receiver 4 ulps above a sphere light (within its surface's error bound): light
# sampling took it for a point of the sphere and read 0 for pi L. Refused.
case("receiver_in_sphere_light_band", "wrong", DISK, [
     ("scene.shapes", [{"geometry": {"type": "sphere", "center": [0.25, -0.125, 0.5], "radius": 0.5},
                        "emission": {"radiance": 1}}]),
     ("measure.irradiance.at", [0.25, -0.125, 1.0000004768371582]),
     ("measure.irradiance.normal", [0, 0, -1])], 2, "measure.irradiance.at", "error bound")
# The same band on the other side and about other curved or planar lights (session 46):
# 4 ulps inside a sphere light emitting inward, 5e-7 inside a 60-degree cap facing its
# wall, 1e-6 above a tilted unit disk light (band 1.4e-6 there), and as high 2e-6 beyond
# its rim: `light` read 0, 8e-6, 1.4e-4 for pi and 2e-6 for 0.17. Refused. Beyond the
# band, 1e-5 inside, a receiver is valid.
IN_SPHERE = [("scene.shapes", [{"geometry": {"type": "sphere", "center": [0.25, -0.125, 0.5], "radius": 0.5},
                                "flip_normals": True, "emission": {"radiance": 1}}]),
             ("measure.irradiance.normal", [0, 0, 1])]
case("receiver_in_sphere_light_band_inside", "wrong", DISK,
     IN_SPHERE + [("measure.irradiance.at", [0.25, -0.125, 0.9999997615814209])], 2,
     "measure.irradiance.at", "scene.shapes[0] (sphere)")
case("receiver_inside_sphere_light_beyond_band", "baseline", DISK,
     IN_SPHERE + [("measure.irradiance.at", [0.25, -0.125, 0.99999])], "valid")
case("receiver_in_cap_light_band", "wrong", CAP, [("measure.irradiance.at", [0, 0, 0.9999995])], 2,
     "measure.irradiance.at", "(spherical cap)")
case("receiver_in_disk_light_band", "wrong", DISK, [
     ("scene.shapes", [{"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0.6, 0.8], "radius": 1},
                        "emission": {"radiance": 1}}]),
     ("measure.irradiance.at", [0, 6e-7, 8e-7]),
     ("measure.irradiance.normal", [0, -0.6, -0.8])], 2, "measure.irradiance.at", "(disk)")
case("receiver_in_disk_light_band_beyond_rim", "wrong", DISK, [
     ("scene.shapes", [{"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0.6, 0.8], "radius": 1},
                        "emission": {"radiance": 1}}]),
     ("measure.irradiance.at", [1.000002, 6e-7, 8e-7]),
     ("measure.irradiance.normal", [0, -0.6, -0.8])], 2, "measure.irradiance.at", "(disk)")
# Moving lights too (found in review: the check skipped every shape with a velocity): a
# tilted disk moving in its own plane at 0.001 under a receiver 1e-6 above it read
# 3.4e-6 for pi with `light`, a sphere light moving at 1e-30 the same 0 as a still one.
case("receiver_in_moving_disk_light_band", "wrong", DISK, [
     ("scene.shapes", [{"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0.6, 0.8], "radius": 1},
                        "emission": {"radiance": 1}, "velocity": [0.001, 0, 0]}]),
     ("time", {"shutter": [0, 1]}),
     ("measure.irradiance.at", [0, 6e-7, 8e-7]),
     ("measure.irradiance.normal", [0, -0.6, -0.8])], 2, "measure.irradiance.at", "(disk)")
case("receiver_in_slow_sphere_light_band", "wrong", DISK, [
     ("scene.shapes", [{"geometry": {"type": "sphere", "center": [0.25, -0.125, 0.5], "radius": 0.5},
                        "emission": {"radiance": 1}, "velocity": [1e-30, 0, 0]}]),
     ("time", {"shutter": [0, 1]}),
     ("measure.irradiance.at", [0.25, -0.125, 1.0000004768371582]),
     ("measure.irradiance.normal", [0, 0, -1])], 2, "measure.irradiance.at", "(sphere)")
# A view factor is geometry: a band read F × its width (60 for 0.2), a bin F × its width,
# and reflective shapes added interreflections (0.216 for 0.200). Refused.
case("flux_view_factor_spectral", "wrong", FLUX, [("spectral", {"band": [400, 700]})], 2,
     "measure.flux.view_factor", "not spectral")
case("flux_view_factor_reflective", "wrong", FLUX, [("scene.materials", {"w": {"type": "lambertian", "albedo": 0.9}}),
     ("scene.shapes.1.material", "w")], 2, "measure.flux.view_factor", "scatters")
case("flux_view_factor_two_sided", "wrong", FLUX, [("scene.shapes.0.emission.two_sided", True)], 2,
     "measure.flux.view_factor")
case("flux_view_factor_two_emitters", "wrong", FLUX, [("scene.shapes.1.emission", {"radiance": 1})], 2,
     "measure.flux.view_factor")
case("flux_view_factor_shape_and_sky", "wrong", FLUX, [("scene.emitters", [{"type": "constant", "radiance": 1}])], 2,
     "measure.flux.view_factor", contains="shapes with `emission`: 1, other lights: 1")
case("flux_view_factor_point_light", "wrong", FLUX, [("scene.shapes.0.emission", DELETE),
     ("scene.emitters", [{"type": "point", "position": [0, 0, 2], "intensity": 1}])], 2, "measure.flux.view_factor")
case("flux_view_factor_blackbody", "wrong", FLUX,
     [("scene.shapes.0.emission.spectrum", {"blackbody": {"temperature": 5000}}),
      ("spectral", {"band": [400, 700]})], 2, "measure.flux.view_factor")
case("flux_view_factor_str", "baseline", FLUX, [("measure.flux.view_factor", "yes")], 2, "measure")
case("flux_estimator_area", "baseline", FLUX, [("estimators", ["area"])], 2, "estimators[0]")
case("flux_valid", "baseline", FLUX, [], "valid")
case("flux_without_view_factor_valid", "baseline", FLUX, [("measure.flux.view_factor", False)], "valid")

# Closed forms at extreme parameters (session 38): a finite reference wherever the true
# value is finite. Before, perpendicular rectangles with a side of 5e-324 or 1e308 and the
# Fresnel average at eta = 1e-39 or 1e39 were "non-finite result" errors, Planck's law at
# 1e-39 m NaN, and parallel rectangles beyond 1e4 × the shorter side refused.
PAR_REF = dict(FLUX, reference={"closed_form": "view_factor_parallel_rectangles", "width": 1, "length": 1,
                                "separation": 1})
sweep("parallel_reference_separation", PAR_REF, "reference.separation", "reference.separation",
      outcomes("valid", m1=2, zero=2, str=2))
PERP_REF = dict(FLUX, reference={"closed_form": "view_factor_perpendicular_rectangles", "common_edge": 1,
                                 "width": 1, "height": 1})
sweep("perpendicular_reference_width", PERP_REF, "reference.width", "reference.width",
      outcomes("valid", m1=2, zero=2, str=2))
FRESNEL_REF = dict(ALBEDO, reference={"closed_form": "fresnel_dielectric_average", "eta": 1.5})
sweep("fresnel_average_reference_eta", FRESNEL_REF, "reference.eta", "reference.eta",
      outcomes("valid", m1=2, zero=2, str=2))
PLANCK_REF = dict(ALBEDO, reference={"closed_form": "planck_radiance", "wavelength": 5e-7, "temperature": 5778})
sweep("planck_reference_wavelength", PLANCK_REF, "reference.wavelength", "reference.wavelength",
      outcomes("valid", m1=2, zero=2, str=2))

# ---------------------------------------------------------------- verify
case("verify_f32_radiance", "f32", DISK, [("scene.shapes.0.emission.radiance", 1e39)], 2,
     "scene.shapes[0].emission.radiance", cmd="verify")
case("verify_valid", "baseline", REF, [], "valid", cmd="verify")
entry("verify_empty_folder", "wrong", ["verify", "{empty_dir}", "--no-chi2"], 2, "no case files")
entry("verify_dev_zero", "hang", ["verify", "/dev/zero", "--no-chi2"], 2, "regular file")
entry("verify_missing", "baseline", ["verify", "{corpus}/nope.json"], 2, "no such file")
entry("verify_samples_one", "wrong", ["verify", "{corpus}/cases/verify_valid.json", "--samples", "1"], 2, "--samples", "256")
entry("verify_samples_max", "hang", ["verify", "{corpus}/cases/verify_valid.json", "--samples", "18446744073709551615"], 2,
      "--samples")
entry("verify_seed_negative", "unclear", ["verify", "{corpus}/cases/verify_valid.json", "--seed", "-1"], 2, "--seed")
entry("verify_threads_negative", "unclear", ["verify", "{corpus}/cases/verify_valid.json", "--threads", "-1"], 2, "--threads")
# Both outputs on one file: the page replaced the JSON.
entry("verify_json_and_html_one_file", "unclear",
      ["verify", "{corpus}/cases/verify_valid.json", "--samples", "4096", "--no-chi2", "--json", "{tmp}/v.out",
       "--html", "{tmp}/v.out"], 2, "--html", "is the file --json names")
entry("verify_json_leftover", "leftover",
      ["verify", "{corpus}/cases/verify_valid.json", "--samples", "4096", "--no-chi2", "--json", "{tmp}/out.json"],
      "valid", pre_files=[".out.json.tmp4294967294"], no_leftovers=True)

# ---------------------------------------------------------------- estimate (command line)
V = "{corpus}/cases/valid_disk.json"
entry("estimate_samples_zero", "wrong", ["estimate", V, "--samples", "0"], 2, "--samples", "256")
entry("estimate_samples_one", "wrong", ["estimate", V, "--samples", "1"], 2, "--samples", "256")
entry("estimate_samples_max", "hang", ["estimate", V, "--samples", "18446744073709551615"], 2, "--samples")
entry("estimate_samples_2p40_plus_1", "hang", ["estimate", V, "--samples", "1099511627777"], 2, "--samples")
entry("estimate_samples_negative", "unclear", ["estimate", V, "--samples", "-1"], 2, "--samples", "256")
entry("estimate_samples_text", "baseline", ["estimate", V, "--samples", "lots"], 2, "--samples")
entry("estimate_seed_negative", "unclear", ["estimate", V, "--seed", "-1"], 2, "--seed")
entry("estimate_threads_huge", "hang", ["estimate", V, "--threads", "1000000000"], 2, "--threads")
entry("estimate_threads_zero", "baseline", ["estimate", V, "--threads", "0", "--samples", "4096"], 2, "--threads")
entry("estimate_threads_negative", "unclear", ["estimate", V, "--threads", "-1"], 2, "--threads")
entry("estimate_dev_zero", "hang", ["estimate", "/dev/zero"], 2, "regular file")
entry("estimate_dev_urandom", "hang", ["estimate", "/dev/urandom"], 2, "regular file")
entry("estimate_big_file", "hang", ["estimate", "{big}"], 2, "limit")
entry("estimate_folder", "baseline", ["estimate", "{empty_dir}"], 2, "folder")
entry("estimate_fifo", "hang", ["estimate", "{fifo}"], 2, "regular file")
entry("judge_render_fifo", "hang", ["judge", "{corpus}/cases/verify_valid.json", "{fifo}"], 2, "regular file")
entry("estimate_estimator_unknown", "baseline", ["estimate", V, "--estimator", "magic"], 2, "--estimator",
      "light, bsdf, mis, mis_balance, uniform, cosine, area")
entry("estimate_estimator_wrong", "baseline", ["estimate", V, "--estimator", "area", "--samples", "4096"], 2, "--estimator")
entry("estimate_sampler_unknown", "baseline", ["estimate", V, "--sampler", "halton"], 2, "--sampler")
entry("estimate_valid_sobol", "baseline", ["estimate", V, "--sampler", "sobol", "--samples", "256"], "valid")

# ---------------------------------------------------------------- chi2
NOT_FOLDER = "is a file, not a folder"
L = '{"type":"lambertian","albedo":0.5}'
entry("chi2_samples_zero", "wrong", ["chi2", L, "--samples", "0", "--out", "{tmp}"], 2, "--samples", "40960")
entry("chi2_samples_ten", "wrong", ["chi2", L, "--samples", "10", "--out", "{tmp}"], 2, "--samples", "40960")
entry("chi2_samples_max", "hang", ["chi2", L, "--samples", "18446744073709551615", "--out", "{tmp}"], 2, "--samples")
entry("chi2_wo_e308", "wrong", ["chi2", L, "--wo", "1e308,0", "--samples", "40960", "--out", "{tmp}"], 2, "--wo")
entry("chi2_wo_theta_200", "wrong", ["chi2", L, "--wo", "200,0", "--samples", "40960", "--out", "{tmp}"], 2, "--wo")
entry("chi2_wo_negative", "unclear", ["chi2", L, "--wo", "-30,0", "--samples", "40960", "--out", "{tmp}"], 2, "--wo", "[0, 180]")
entry("chi2_wo_phi_400", "wrong", ["chi2", L, "--wo", "30,400", "--samples", "40960", "--out", "{tmp}"], 2, "--wo",
      "[-360, 360]")
entry("chi2_wo_text", "baseline", ["chi2", L, "--wo", "up", "--out", "{tmp}"], 2, "--wo")
# A model of delta lobes only has no density: it failed as "too few samples" at any count.
for model in ['{"type":"conductor","eta":1.5,"k":3}', '{"type":"dielectric","eta":1.5}']:
    entry("chi2_delta_only_" + json.loads(model)["type"], "unclear",
          ["chi2", model, "--samples", "40960", "--out", "{tmp}"], 2, "bsdf", "only Dirac delta lobes")
entry("chi2_out_is_file", "unclear", ["chi2", L, "--samples", "40960", "--out", "{file}"], 3, contains=NOT_FOLDER)
entry("chi2_bsdf_bad_json", "unclear", ["chi2", "{", "--out", "{tmp}"], 2, "bsdf",
      "invalid BSDF JSON: EOF while parsing an object", absent=NO_FIELD)
entry("chi2_bsdf_albedo_sub", "f32", ["chi2", '{"type":"lambertian","albedo":1e-39}', "--out", "{tmp}"], 2, "albedo",
      "underflows f32")
entry("chi2_bsdf_albedo_e39", "f32", ["chi2", '{"type":"lambertian","albedo":1e39}', "--out", "{tmp}"], 2, "albedo")
entry("chi2_bsdf_unknown", "baseline", ["chi2", '{"type":"velvet"}', "--out", "{tmp}"], 2, "bsdf")
entry("chi2_seed_negative", "unclear", ["chi2", L, "--seed", "-1", "--out", "{tmp}"], 2, "--seed")
entry("chi2_valid", "baseline", ["chi2", L, "--samples", "40960", "--out", "{tmp}"], "valid")

# ---------------------------------------------------------------- render
case("render_valid", "baseline", CAMERA, [], "valid", cmd="render")
case("render_width_2p63", "crash", CAMERA, [("camera.width", 9223372036854775808), ("camera.height", 2)], 2,
     "camera.width", cmd="render")
case("render_width_height_overflow", "unclear", CAMERA, [("camera.width", 4294967296), ("camera.height", 4294967296)], 2,
     "camera.width", "×", cmd="render")
sweep("render_width", CAMERA, "camera.width", "camera.width", ALL2, cmd="render")
sweep("render_height", CAMERA, "camera.height", "camera.height", ALL2, cmd="render")
sweep("render_fov", CAMERA, "camera.fov_degrees", "camera.fov_degrees", ALL2, cmd="render")
sweep("render_position", CAMERA, "camera.position", "camera.position", COORD, vec=(2, [0, 0, 0]), cmd="render")
# look_at − position is the view direction: its only non-zero component.
# (a coordinate: 1e-39 from the eye is a direction f64 normalises; 5e-324 is not).
sweep("render_look_at", CAMERA, "camera.look_at", "camera.look_at", outcomes(2, m1="valid", sub="valid"),
      vec=(2, [0, 0, 1]), cmd="render")
sweep("render_up", CAMERA, "camera.up", "camera.up", DIRZ, vec=(1, [0, 1, 0]), cmd="render")
case("render_no_camera", "baseline", DISK, [], 2, "camera", cmd="render")
entry("render_spp_zero", "wrong", ["render", "{corpus}/cases/render_valid.json", "--spp", "0", "-o", "{tmp}/o.exr"], 2, "--spp")
entry("render_spp_max", "hang", ["render", "{corpus}/cases/render_valid.json", "--spp", "18446744073709551615",
                                 "-o", "{tmp}/o.exr"], 2, "--spp")
entry("render_spp_negative", "unclear", ["render", "{corpus}/cases/render_valid.json", "--spp", "-1", "-o", "{tmp}/o.exr"],
      2, "--spp")
case("render_pixels_over_limit", "hang", CAMERA, [("camera.width", 8192), ("camera.height", 8193)], 2,
     "camera.width", cmd="render")
case("render_pixels_1m", "baseline", CAMERA, [("camera.width", 1024), ("camera.height", 1025)], "valid", cmd="render",
     extra=["--max-depth", "0"])
# 1024 × 1025 pixels × 2^20 spp is just over 2^40 paths.
entry("render_samples_over_limit", "hang", ["render", "{corpus}/cases/render_pixels_1m.json", "--spp", "1048576",
                                            "-o", "{tmp}/o.exr"], 2, "--spp", "at most 2^40")
entry("render_exposure_65", "wrong", ["render", "{corpus}/cases/render_valid.json", "--spp", "1", "--exposure", "65",
                                      "-o", "{tmp}/o.png"], 2, "--exposure")
entry("render_png", "baseline", ["render", "{corpus}/cases/render_valid.json", "--spp", "1", "--exposure", "-64",
                                 "-o", "{tmp}/o.png"], "valid", no_leftovers=True)
entry("render_dev_zero", "hang", ["render", "/dev/zero", "-o", "{tmp}/o.exr"], 2, "regular file")

# ---------------------------------------------------------------- report
R = "{corpus}/cases/valid_disk.json"
REP = ["--max-samples", "256", "--sampler", "independent", "--out", "{tmp}/rep"]
entry("report_min_samples_overflow", "wrong", ["report", R, "--min-samples", "9223372036854775809"] + REP, 2, "--min-samples")
entry("report_max_samples_max", "baseline", ["report", R, "--max-samples", "18446744073709551615", "--out", "{tmp}/rep"], 2,
      "--max-samples")
entry("report_budget_negative", "unclear", ["report", R, "--budget", "-5"] + REP, 2, "--budget")
entry("report_budget_zero", "baseline", ["report", R, "--budget", "0"] + REP, 2, "--budget")
entry("report_threads_huge", "hang", ["report", R, "--threads", "1000000"] + REP, 2, "--threads")
entry("report_shard_bad", "baseline", ["report", R, "--shard", "3/2"] + REP, 2, "--shard")
entry("report_shard_negative", "unclear", ["report", R, "--shard", "-1/2"] + REP, 2, "--shard")
entry("report_empty_folder", "wrong", ["report", "{empty_dir}"] + REP, 2, "no case files")
# Case ids whose report files are the folder's own (`index.json` was replaced by the index;
# `shard-0-of-1.json` was read as a partial by `merge --out`, then replaced by the report),
# or one another's (`a/b` and `a.b` both write `a.b.json`).
REPORT_FOLDERS = {
    "report/reserved_index": ["index.json"],
    "report/reserved_shard": ["shard-0-of-1.json"],
    "report/stem_clash": ["a/b.json", "a.b.json"],
    # `p.transient.svg` is the transient plot of a time-binned case `p`: a case whose id
    # is `p.transient` had its convergence plot written over by it.
    "report/transient_clash": ["p.transient.json"],
}
for folder, contains in [("report/reserved_index", "a name the report folder keeps for its index"),
                         ("report/reserved_shard", "a name the report folder keeps for its shard partials"),
                         ("report/stem_clash", "writes `a.b.json`, as"),
                         ("report/transient_clash", "the name of the transient plot of a case `p`")]:
    entry(folder.replace("/", "_"), "wrong", ["report", "{corpus}/" + folder] + REP, 2, ".json", contains)
entry("report_f32_case", "f32", ["report", "{corpus}/cases/emission_radiance_e39.json"] + REP, 2,
      "scene.shapes[0].emission.radiance")
entry("report_valid", "baseline", ["report", R] + REP, "valid")
entry("report_leftover", "leftover", ["report", R, "--max-samples", "256", "--sampler", "independent", "--out", "{tmp}"],
      "valid", pre_files=[".index.json.tmp4294967294"], no_leftovers=True)

# ---------------------------------------------------------------- merge
partial = json.load(open(os.path.join(HERE, "assets/shard-0-of-1.json")))
def merge_case(name, cls, edit, expect, field=None, contains=None):
    doc = copy.deepcopy(partial)
    edit(doc)
    write("merge/%s/shard-0-of-1.json" % name, json.dumps(doc))
    entry(name, cls, ["merge", "{corpus}/merge/%s" % name, "--out", "{tmp}/rep"], expect, field, contains)
merge_case("merge_index_out_of_range", "crash", lambda d: d["shard"].update(index=7), 2, "shard.index")
merge_case("merge_count_zero", "crash", lambda d: d["shard"].update(count=0), 2, "shard.count")
merge_case("merge_count_huge", "hang", lambda d: d["shard"].update(count=4294967295), 2, "missing shard(s) 1, 2")
merge_case("merge_count_string", "baseline", lambda d: d["shard"].update(count="one"), 2, "shard.count")
merge_case("merge_wrong_format", "baseline", lambda d: d.update(format="other/1"), 2, "format")
merge_case("merge_valid", "baseline", lambda d: None, "valid")
# Batch records no run writes (the schema cannot say these): they once merged silently,
# a zero count into a different estimate, a negative m2 into a missing standard error,
# means of 1e308 into `"estimate": null`, a batch of 1e308 s into a report without fits.
B0 = lambda d: d["cases"][0]["series"][0]["points"][0]["batches"][0]
BF = "cases[0].series[0].points[0].batches[0]."
merge_case("merge_seconds_e308", "wrong", lambda d: B0(d).update(seconds=1e308), 2, BF + "seconds")
merge_case("merge_batch_mean_e308", "wrong", lambda d: B0(d).update(mean=1e308), 2, BF + "mean")
merge_case("merge_batch_mean_e39", "f32", lambda d: B0(d).update(mean=-1e39), 2, BF + "mean")
merge_case("merge_batch_m2_e308", "wrong", lambda d: B0(d).update(m2=1e308), 2, BF + "m2")
# Settings no `report` writes: min_samples 0 made the merge shift by 64 (a panic with
# overflow checks, no points without).
merge_case("merge_settings_min_zero", "crash", lambda d: d["settings"].update(min_samples=0, max_samples=0), 2,
           "settings.min_samples")
merge_case("merge_settings_max_below_min", "wrong", lambda d: d["settings"].update(min_samples=512, max_samples=256),
           2, "settings.max_samples")
merge_case("merge_settings_batches_64", "wrong", lambda d: d["settings"].update(batches=64), 2, "settings.batches")
merge_case("merge_batch_count_zero", "wrong", lambda d: B0(d).update(count=0), 2, BF + "count")
merge_case("merge_batch_count_more", "wrong", lambda d: B0(d).update(count=B0(d)["count"] + 1), 2, BF + "count")
merge_case("merge_batch_m2_negative", "wrong", lambda d: B0(d).update(m2=-5), 2, BF + "m2")
merge_case("merge_batch_index_128", "wrong", lambda d: B0(d).update(batch=128), 2, BF + "batch")
merge_case("merge_batch_seconds_negative", "wrong", lambda d: B0(d).update(seconds=-1), 2, BF + "seconds")
merge_case("merge_point_samples_odd", "wrong",
           lambda d: d["cases"][0]["series"][0]["points"][0].update(samples=777), 2,
           "cases[0].series[0].points[0].samples")
merge_case("merge_unknown_field", "wrong", lambda d: B0(d).update(extra=1), 2, BF + "extra")
merge_case("merge_unknown_top_field", "wrong", lambda d: d.update(colour=1), 2, "colour")
write("merge/merge_trailing/shard-0-of-1.json", json.dumps(partial) + '{"x": 1}')
entry("merge_trailing", "wrong", ["merge", "{corpus}/merge/merge_trailing", "--out", "{tmp}/rep"], 2, None,
      "shard-0-of-1.json: trailing characters")
entry("merge_dev_zero", "hang", ["merge", "{corpus}/merge/devzero", "--out", "{tmp}/rep"], 2, "no shard partial")
entry("merge_nothing", "baseline", ["merge", "{empty_dir}", "--out", "{tmp}/rep"], 2, "shard")

# ---------------------------------------------------------------- judge
# A render of verify_valid (the on-axis disk, E = pi L R^2/(R^2 + h^2) = pi/5): every
# pixel at the reference passes exactly; a pixel whose channels average to it but hold a
# negative one (-0.5, y, y) still fails (negative radiance is never averaged away).
J = "{corpus}/cases/verify_valid.json"
E_DISK = 3.141592653589793 / 5
Y = (3 * E_DISK + 0.5) / 2
def a(name):
    return "{corpus}/assets/%s" % name
entry("judge_valid", "baseline", ["judge", J, a("render_ok.exr"), a("render_ok.exr")], "valid")
entry("judge_negative_channel", "wrong", ["judge", J, a("render_ok.exr"), a("render_negative_channel.exr")], 1,
      contains="1 pixels with a negative channel (negative radiance), the first at (1, 1) = (-0.5, ")
entry("judge_nan_pixel", "baseline", ["judge", J, a("render_ok.exr"), a("render_nan.exr")], 1,
      contains="1 non-finite pixels, the first at (2, 0)")
# No finite pixel at all: the judgement read `0.000000 ± inf`, z −inf and an estimate of 0.0.
entry("judge_all_nan", "wrong", ["judge", J, a("render_all_nan.exr"), a("render_all_nan.exr"), "--json"], 1,
      contains='"estimate": null', absent="inf")
entry("judge_one_finite_render", "wrong", ["judge", J, a("render_ok.exr"), a("render_all_nan.exr")], 1,
      contains="1 finite replicate: fewer than two", absent="(exact)")
entry("judge_huge_header", "hang", ["judge", J, a("env_huge_header.exr")], 2, "env_huge_header.exr", "200000 × 200000")
entry("judge_header_only", "crash", ["judge", J, a("render_header_only.exr")], 2, "render_header_only.exr", "truncated")
entry("judge_truncated", "crash", ["judge", J, a("render_ok.exr"), a("render_truncated.exr")], 2,
      "render_truncated.exr", "EXR")
entry("judge_size_mismatch", "baseline", ["judge", J, a("render_ok.exr"), a("render_small.exr")], 2,
      "render_small.exr", "expected 4 × 2")
entry("judge_one_pixel", "wrong", ["judge", J, a("render_one_pixel.exr")], 2, "render_one_pixel.exr",
      "one render of one pixel")
entry("judge_not_exr", "baseline", ["judge", J, "{corpus}/cases/valid_disk.json"], 2, "valid_disk.json", "EXR")
entry("judge_render_over_1gib", "hang", ["judge", J, "{big_asset}"], 2, "big.exr", "limit")
entry("judge_render_folder", "baseline", ["judge", J, "{empty_dir}"], 2, "folder")
entry("judge_render_dev_zero", "hang", ["judge", J, "/dev/zero"], 2, "regular file")
entry("judge_case_dev_zero", "hang", ["judge", "/dev/zero", a("render_ok.exr")], 2, "regular file")
entry("judge_case_bad", "baseline", ["judge", "{corpus}/cases/emission_radiance_m1.json", a("render_ok.exr")], 2,
      "scene.shapes[0].emission.radiance")
entry("judge_no_render", "baseline", ["judge", J], 2, "RENDER.exr")
entry("judge_suite_empty", "baseline", ["judge", "--suite", "{empty_dir}"], 2, "suite.json")
# A render whose block of line 1 claims line 0 (render_ok.exr otherwise): the reader takes
# it and line 1 was once read as pixels of 0; an empty file says it is empty.
entry("judge_missing_line", "wrong", ["judge", J, a("render_ok.exr"), a("render_missing_line.exr")], 2,
      "render_missing_line.exr", "line 1 of 2 has no pixel data")
entry("judge_empty_render", "unclear", ["judge", J, a("render_ok.exr"), "{corpus}/assets/render_empty.exr"], 2,
      "render_empty.exr", "the file is empty")
# Cases no renderer's sensor measures (export refuses them): an emitter's power (with a
# reference, once judged against the pixel means and passed) and a solid angle.
SPHERE_AREA = 4 * 3.141592653589793
case("judge_power_case", "wrong",
     dict(POWER, reference={"closed_form": "lambertian_power", "radiance": 1, "area": SPHERE_AREA}), [], 2,
     "measure", "power and intensity of an emitter have no renderer sensor", cmd="judge",
     extra=[a("render_ok.exr"), a("render_ok.exr")])
case("judge_solid_angle_case", "wrong", SOLID, [], 2, "measure", "a geometric integral", cmd="judge",
     extra=[a("render_ok.exr"), a("render_ok.exr")])
# export.json as an export writes it (verify_valid's case, 4 × 2 pixels, scale 1), and with
# numbers no export writes: a scale of 0 or 1e-320 once printed `± inf`, -1 a negative
# estimate; a width of 0 blamed the render for its size.
VERIFY_VALID = json.dumps(REF, indent=1)
MANIFEST = {"renderer": "mitsuba", "source": "verify_valid.json", "name": "disk on axis", "case": "case.json",
            "scene": "scene.xml", "sensor": "irradiance", "width": 4, "height": 2, "scale": 1.0,
            "conventions": []}
def export_case(name, cls, edits, expect, field=None, contains=None):
    m = dict(MANIFEST, **edits)
    write("export/%s/export.json" % name, json.dumps(m, indent=1))
    write("export/%s/case.json" % name, VERIFY_VALID)
    entry(name, cls, ["judge", "{corpus}/export/%s/case.json" % name, a("render_ok.exr"), a("render_ok.exr")], expect,
          field, field and "export.json: %s: %s" % (field, contains or ""))
export_case("judge_export_valid", "baseline", {}, "valid")
export_case("judge_export_scale_zero", "wrong", {"scale": 0}, 2, "scale")
export_case("judge_export_scale_subnormal", "wrong", {"scale": 1e-320}, 2, "scale")
export_case("judge_export_scale_negative", "wrong", {"scale": -1}, 2, "scale")
export_case("judge_export_scale_e308", "wrong", {"scale": 1e308}, 2, "scale")
export_case("judge_export_width_zero", "wrong", {"width": 0}, 2, "width")
export_case("judge_export_height_zero", "wrong", {"height": 0}, 2, "height")
export_case("judge_export_pixels_over_limit", "wrong", {"width": 8192, "height": 8193}, 2, "width × height",
            "width × height")
export_case("judge_export_width_huge", "wrong", {"width": 2**63, "height": 2}, 2, "width", "width × height")
# The height alone too large once blamed the width.
export_case("judge_export_height_huge", "wrong", {"width": 2, "height": 2**63}, 2, "height", "width × height")
# The same check for a suite (one case `c` with two renders, render_ok.exr's copies,
# written below): valid, and with a negative scale.
# Its ids: one listed twice (its renders once counted twice in the family), and ids leaving
# the suite folder (`..`, absolute) are refused naming cases[i].
SUITES = {"judge_suite_valid": (1.0, ["c"]), "judge_suite_scale_negative": (-1, ["c"]),
          "judge_suite_duplicate_id": (1.0, ["c", "c"]), "judge_suite_id_parent": (1.0, ["c", "../judge_suite_valid/c"]),
          "judge_suite_id_absolute": (1.0, ["/tmp"]),
          # Links (made below): to the suite's own `c` (its renders counted twice), and
          # out of the suite; both passed the names' check once.
          "judge_suite_id_link_twin": (1.0, ["c", "twin"]),
          "judge_suite_id_link_outside": (1.0, ["c", "outside"])}
SUITE_LINKS = {"judge_suite_id_link_twin": ("twin", "c"),
               "judge_suite_id_link_outside": ("outside", "../judge_suite_valid/c")}
for name, (scale, ids) in SUITES.items():
    write("export/%s/suite.json" % name, json.dumps({"renderer": "mitsuba", "cases": ids, "refused": []}))
    write("export/%s/c/export.json" % name, json.dumps(dict(MANIFEST, scale=scale), indent=1))
    write("export/%s/c/case.json" % name, VERIFY_VALID)
entry("judge_suite_valid", "baseline", ["judge", "--suite", "{corpus}/export/judge_suite_valid"], "valid")
entry("judge_suite_scale_negative", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_scale_negative"], 2,
      "scale", "c/export.json: scale: ")
entry("judge_suite_duplicate_id", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_duplicate_id"], 2,
      "cases[1]", "suite.json: cases[1]: `c` is listed twice")
entry("judge_suite_id_parent", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_id_parent"], 2,
      "cases[1]", "not a folder inside the suite")
entry("judge_suite_id_absolute", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_id_absolute"], 2,
      "cases[0]", "not a folder inside the suite")
# A suite case's `case` is a file name beside its renders: a path out of the folder judged
# the renders against another case.
write("export/judge_suite_case_outside/suite.json", json.dumps({"renderer": "mitsuba", "cases": ["c"], "refused": []}))
write("export/judge_suite_case_outside/c/export.json",
      json.dumps(dict(MANIFEST, case="../../judge_suite_valid/c/case.json"), indent=1))
entry("judge_suite_case_outside", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_case_outside"], 2,
      "case", "c/export.json: case: must name the case file beside it")
entry("judge_suite_id_link_twin", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_id_link_twin"], 2,
      "cases[1]", "is the folder of cases[0]")
entry("judge_suite_id_link_outside", "wrong", ["judge", "--suite", "{corpus}/export/judge_suite_id_link_outside"], 2,
      "cases[1]", "not a folder inside the suite (links resolved)")

# ---------------------------------------------------------------- export
entry("export_valid", "baseline", ["export", V, "--to", "mitsuba", "--out", "{tmp}/x"], "valid", no_leftovers=True)
entry("export_inexpressible", "baseline", ["export", V, "--to", "pbrt", "--out", "{tmp}/x"], 2, "valid_disk.json",
      "no irradiance sensor")
entry("export_target_unknown", "baseline", ["export", V, "--to", "blender", "--out", "{tmp}/x"], 2, "--to")
entry("export_case_bad", "baseline", ["export", "{corpus}/cases/emission_radiance_m1.json", "--to", "pbrt",
                                      "--out", "{tmp}/x"], 2, "scene.shapes[0].emission.radiance")
entry("export_case_dev_zero", "hang", ["export", "/dev/zero", "--to", "pbrt", "--out", "{tmp}/x"], 2, "regular file")
entry("export_all_empty_folder", "wrong", ["export", "--all", "{empty_dir}", "--to", "pbrt", "--out", "{tmp}/x"], 2,
      "no case files")
entry("export_two_cases", "baseline", ["export", V, V, "--to", "pbrt", "--out", "{tmp}/x"], 2, "one case file")

# ---------------------------------------------------------------- outputs in the way (exit 3)
entry("export_out_is_file", "unclear", ["export", V, "--to", "mitsuba", "--out", "{file}"], 3, contains=NOT_FOLDER)
entry("export_out_below_file", "unclear", ["export", V, "--to", "mitsuba", "--out", "{file}/sub"], 3,
      contains=NOT_FOLDER)
entry("report_out_is_file", "unclear", ["report", R, "--max-samples", "256", "--sampler", "independent",
                                        "--out", "{file}"], 3, contains=NOT_FOLDER)
# Bad input is told before an output in the way (exit 2, not 3).
entry("report_bad_case_out_is_file", "unclear", ["report", "{corpus}/cases/emission_radiance_m1.json", "--out", "{file}"],
      2, "scene.shapes[0].emission.radiance")
entry("export_bad_case_out_is_file", "unclear", ["export", "{corpus}/cases/emission_radiance_m1.json", "--to", "mitsuba",
                                                 "--out", "{file}"], 2, "scene.shapes[0].emission.radiance")
entry("merge_out_is_file", "unclear", ["merge", "{corpus}/merge/merge_valid", "--out", "{file}"], 3,
      contains=NOT_FOLDER)
entry("verify_json_below_file", "unclear", ["verify", J, "--samples", "4096", "--no-chi2", "--json", "{file}/v.json"],
      3, contains=NOT_FOLDER)
entry("render_output_below_file", "unclear", ["render", "{corpus}/cases/render_valid.json", "--spp", "1",
                                              "-o", "{file}/o.exr"], 3, contains=NOT_FOLDER)
# The output is checked before any sampling: with 2^40 samples (report) or 2^32 (chi2) a
# check made after the work would run past the harness's timeout.
entry("report_out_is_file_before_sampling", "hang", ["report", R, "--min-samples", "1099511627776",
                                                     "--max-samples", "1099511627776", "--out", "{file}"], 3,
      contains=NOT_FOLDER)
# render and verify check their output files before the work too (a render of 2^20 spp
# into /proc, which takes no file, once ran to its end before exit 3).
entry("render_out_proc_before_rendering", "hang", ["render", "{corpus}/cases/render_valid.json", "--spp", "1048576",
                                                   "-o", "/proc/o.exr"], 3, contains="takes no new file")
entry("verify_json_is_folder", "unclear", ["verify", J, "--samples", "4096", "--no-chi2", "--json", "{tmp}"], 3,
      contains="is a folder, not a file")
entry("verify_html_proc", "unclear", ["verify", J, "--samples", "4096", "--no-chi2", "--html", "/proc/v.html"], 3,
      contains="takes no new file")
entry("chi2_out_is_file_before_sampling", "hang", ["chi2", L, "--samples", "4294967296", "--out", "{file}"], 3,
      contains=NOT_FOLDER)
# An --out folder that takes no new file (/proc) is found before sampling too, by a probe
# file in the nearest existing folder on the way (it once ran 2^32 samples, or 2^40, first).
entry("chi2_out_proc_before_sampling", "hang", ["chi2", L, "--samples", "4294967296", "--out", "/proc/x"], 3,
      contains="`/proc` takes no new file")
entry("report_out_proc_before_sampling", "hang", ["report", R, "--min-samples", "1099511627776",
                                                  "--max-samples", "1099511627776", "--out", "/proc/rep"], 3,
      contains="`/proc` takes no new file")
# A symbolic link whose target does not exist, as the output folder or on the way to a
# file: the system says "File exists"; the message names the link and its target.
DANGLING = "is a symbolic link to"
entry("report_out_dangling_link", "unclear", ["report", R, "--max-samples", "256", "--sampler", "independent",
                                              "--out", "{dangling}"], 3, contains=DANGLING)
entry("chi2_out_dangling_link", "unclear", ["chi2", L, "--samples", "40960", "--out", "{dangling}"], 3,
      contains=DANGLING)
entry("export_out_below_dangling_link", "unclear", ["export", V, "--to", "mitsuba", "--out", "{dangling}/sub"], 3,
      contains=DANGLING)
entry("merge_out_dangling_link", "unclear", ["merge", "{corpus}/merge/merge_valid", "--out", "{dangling}"], 3,
      contains=DANGLING)
entry("verify_json_below_dangling_link", "unclear", ["verify", J, "--samples", "4096", "--no-chi2", "--json",
                                                     "{dangling}/v.json"], 3, contains=DANGLING)
entry("render_output_below_dangling_link", "unclear", ["render", "{corpus}/cases/render_valid.json", "--spp", "1",
                                                       "-o", "{dangling}/o.exr"], 3, contains=DANGLING)

if __name__ == "__main__":
    ok = [(E_DISK,) * 3] * 8
    write("assets/render_ok.exr", exr(4, 2, ok))
    for name in SUITES:
        for k in range(2):
            write("export/%s/c/renders/%03d.exr" % (name, k), exr(4, 2, ok))
    for name, (link, target) in SUITE_LINKS.items():
        path = os.path.join(HERE, "export", name, link)
        if os.path.lexists(path):
            os.remove(path)
        os.symlink(target, path)
    write("assets/render_negative_channel.exr", exr(4, 2, ok[:5] + [(-0.5, Y, Y)] + ok[6:]))
    write("assets/render_nan.exr", exr(4, 2, ok[:2] + [(float("nan"),) * 3] + ok[3:]))
    write("assets/render_all_nan.exr", exr(4, 2, [(float("nan"),) * 3] * 8))
    write("assets/render_small.exr", exr(2, 2, ok[:4]))
    write("assets/render_one_pixel.exr", exr(1, 1, ok[:1]))
    # A header within the pixel limit (8000 × 8000 < 2^26) whose chunk table alone (8000
    # offsets) is longer than the file.
    write("assets/render_header_only.exr", exr(4, 2, [], claim=(8000, 8000), offsets=False))
    write("assets/render_truncated.exr", exr(4, 2, ok)[:-20])
    missing = bytearray(exr(4, 2, ok))
    second = struct.unpack_from("<Q", missing, len(exr(4, 2, ok, offsets=False)) + 8)[0]
    struct.pack_into("<i", missing, second, 0)
    write("assets/render_missing_line.exr", bytes(missing))
    write("assets/render_empty.exr", b"")
    for folder, files in REPORT_FOLDERS.items():
        for f in files:
            write("%s/%s" % (folder, f), json.dumps(DISK, indent=1))
    for name, text in OBJ_ASSETS.items():
        write("assets/%s.obj" % name, text)
    write("assets/env_ok.exr", exr(4, 2, [(1.0, 1.0, 1.0)] * 8))
    write("assets/env_negative_channel.exr", exr(4, 2, [(1.0, 1.0, 1.0)] * 7 + [(-1.0, 2.0, 2.0)]))
    write("assets/env_huge_header.exr", exr(1, 1, [], claim=(200000, 200000), offsets=False))
    link = os.path.join(HERE, "merge/devzero/shard-0-of-1.json")
    os.makedirs(os.path.dirname(link), exist_ok=True)
    if os.path.lexists(link):
        os.remove(link)
    os.symlink("/dev/zero", link)
    names = [e["name"] for e in ENTRIES]
    assert len(names) == len(set(names)), "duplicate names"
    write("manifest.json", json.dumps({"entries": ENTRIES}, indent=1) + "\n")
    print(len(ENTRIES), "entries")
