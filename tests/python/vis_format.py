"""An independent reader of the .vis file (docs/outputs.md, "The visibility matrix"), in plain
Python, so that the tests can compare the module's matrix with the file's sets without the
module's own code."""

import dataclasses
import struct


@dataclasses.dataclass
class VisCandidate:
    name: str
    type_id: str
    population: str
    position: tuple
    quaternion: tuple  # [w, x, y, z]
    reference_indices: list
    rays_traced: int
    reference_hits: list = dataclasses.field(default_factory=list)  # pixels per cell (version 4)
    interferes: object = None  # the type's `interferes:` (version 5), None when unset
    cost: float = 1.0  # the sensor type's unit cost (the budget objective)
    cost_given: bool = True  # False: no price given, cost is a placeholder (version 9)
    # A camera on an arm (version 11): (robot, joint names, joints), None for a fixed camera.
    arm: object = None


@dataclasses.dataclass
class VisFile:
    version: int
    scene: str
    seed: int
    cell_size: float
    keys: list
    candidates: list
    keep_out: list = dataclasses.field(default_factory=list)  # (name, pose, min, max) (version 5)
    min_separation: object = None  # [m] (version 5)
    kept_out: int = 0  # candidates the keep-out boxes excluded (version 5)
    part_names: list = dataclasses.field(default_factory=list)  # R's target parts (version 6)
    part_of: list = dataclasses.field(default_factory=list)  # per key, its part (version 6)
    exposed: list = dataclasses.field(default_factory=list)  # per key, 1 exposed (version 6)
    exposed_only: bool = False  # unexposed cells left out of R (version 6)
    left_out: list = dataclasses.field(default_factory=list)  # per part, cells left out (version 6)
    physical: bool = False  # observed with the physical sensor model (version 7)
    scene_path: str = ""  # the scene's absolute path, as observe read it (version 10)
    model_paths: list = dataclasses.field(default_factory=list)  # absolute (version 10)
    resource_paths: list = dataclasses.field(default_factory=list)  # absolute (version 10)
    package_paths: list = dataclasses.field(default_factory=list)  # absolute (version 10)
    targets: list = dataclasses.field(default_factory=list)  # --target names (version 10)
    cell_size_override: object = None  # --cell-size [m] (version 10)


class _Reader:
    def __init__(self, data):
        self.data = data
        self.at = 0

    def take(self, fmt):
        size = struct.calcsize(fmt)
        values = struct.unpack_from(fmt, self.data, self.at)
        self.at += size
        return values

    def u32(self):
        return self.take("<I")[0]

    def u64(self):
        return self.take("<Q")[0]

    def f64(self):
        return self.take("<d")[0]

    def string(self):
        length = self.u64()
        text = self.data[self.at:self.at + length].decode("utf-8")
        self.at += length
        return text

    def u32s(self):
        count = self.u64()
        return list(self.take(f"<{count}I"))

    def u16s(self):
        count = self.u64()
        return list(self.take(f"<{count}H"))

    def u64s(self):
        count = self.u64()
        return list(self.take(f"<{count}Q"))

    def optional(self):
        present, value = self.u32(), self.f64()
        return value if present else None


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for byte in data:
        h ^= byte
        h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def read_vis(path):
    """The sets of a format-4 to 11 .vis file, its checksum verified."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"VANTVIS\0", "not a vantage visibility file"
    (stored,) = struct.unpack_from("<Q", data, len(data) - 8)
    assert stored == fnv1a64(data[:-8]), "checksum mismatch"
    r = _Reader(data[:-8])
    r.at = 8
    version = r.u32()
    assert version in (4, 5, 6, 7, 8, 9, 10, 11), f"format version {version}"
    scene, seed = r.string(), r.u64()
    r.u32(), r.u32(), r.f64()  # n, RANSAC iterations and stop coverage
    r.string(), r.optional(), r.u32(), r.optional()  # method, goal, k, budget
    r.optional(), r.optional()  # quality: max incidence, max depth noise
    physical = False
    if version >= 7:
        flag = r.u32()  # the sensor model: 0 ideal, 1 physical
        assert flag <= 1, f"sensor model flag {flag}"
        physical = flag == 1
    cell_size = r.f64()
    keys = r.u64s()
    candidates = []
    for _ in range(r.u64()):
        name, type_id, population = r.string(), r.string(), r.string()
        r.string(), r.string(), r.string()  # sensor id, name, technology
        r.u32(), r.u32()  # width, height
        cost = r.take("<8d")[7]  # fx, fy, cx, cy, near, far, fps, cost
        r.u32(), r.take("<3d"), r.string()  # depth noise: presence, a, b, c, source
        interferes = None
        if version >= 5:
            flag = r.u32()  # 0 unset, 1 false, 2 true
            assert flag <= 2, f"interferes flag {flag}"
            interferes = None if flag == 0 else flag == 2
        if version >= 7 and r.u32():  # second aperture: presence, then its fields
            assert r.u32() <= 2, "second aperture kind"
            r.take("<5d"), r.u32(), r.u32(), r.take("<4d"), r.optional(), r.string()
        position = r.take("<3d")
        quaternion = r.take("<4d")
        indices = r.u32s()
        r.u64s()  # keys seen outside R
        rays = r.u64()
        r.u32s(), r.u64(), r.u64()  # plain cells, target and quality pixels
        hits = r.u16s()
        if version >= 7:
            differs = r.u32()  # the ideal pinhole's cells, when the physical model changed them
            ideal = r.u32s()
            assert differs <= 1 and (differs or not ideal), "ideal cells"
        if version >= 8:
            r.f64(), r.optional()  # noise incidence coefficient, flying-pixel threshold
        cost_given = True
        if version >= 9:
            flag = r.u32()  # 0 the unit cost is given, 1 not given (no price published)
            assert flag <= 1, f"cost-given flag {flag}"
            cost_given = flag == 0
        candidates.append(VisCandidate(name, type_id, population, position, quaternion, indices,
                                       rays, hits, interferes, cost, cost_given))
    vis = VisFile(version, scene, seed, cell_size, keys, candidates)
    vis.physical = physical
    if version >= 5:
        for _ in range(r.u64()):  # keep-out boxes
            name = r.string()
            pose = r.take("<7d")  # x y z, w x y z
            low, high = r.take("<3d"), r.take("<3d")
            r.string(), r.u32()  # file, line
            vis.keep_out.append((name, pose, low, high))
        vis.min_separation = r.optional()
        r.string(), r.u32()  # its file, line
        vis.kept_out = r.u64()
    if version >= 6:
        vis.part_names = [r.string() for _ in range(r.u64())]
        vis.part_of = r.u32s()
        vis.exposed = r.u32s()
        vis.exposed_only = r.u32() != 0
        vis.left_out = r.u64s()
    if version >= 10:  # how observe read the scene, so that `select` reloads it from any folder
        vis.scene_path = r.string()  # absolute
        vis.model_paths, vis.resource_paths, vis.package_paths, vis.targets = (
            [r.string() for _ in range(r.u64())] for _ in range(4))
        vis.cell_size_override = r.optional()
    if version >= 11:  # each camera on an arm's configuration (written only when there is one)
        arms = []
        for _ in range(r.u64()):  # the distinct arms: robot, joint names
            robot = r.string()
            arms.append((robot, [r.string() for _ in range(r.u64())]))
        assert arms, "format 11 without an arm"
        for candidate in vis.candidates:
            row = r.u32()  # 0 a fixed camera, else 1 + its arm's row
            assert row <= len(arms), f"arm row {row}"
            if row:
                robot, joint_names = arms[row - 1]
                joints = list(r.take(f"<{len(joint_names)}d"))
                candidate.arm = (robot, joint_names, joints)
    assert r.at == len(r.data), "trailing bytes"
    return vis


def unpack_key(key):
    """The integer cell (i, j, k) of a packed key: 21 bits per axis, offset 2^20, x highest."""
    mask = (1 << 21) - 1
    offset = 1 << 20
    return ((key >> 42) & mask) - offset, ((key >> 21) & mask) - offset, (key & mask) - offset
