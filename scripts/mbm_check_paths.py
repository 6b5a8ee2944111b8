#!/usr/bin/env python3
"""Independent check of motion-planning paths on MotionBenchMaker problems.

Reads the paths `tabula motion bench --mbm ... --paths OUT.json` wrote, rebuilds every
problem's scene from its YAML with python-fcl (boxes, cylinders, spheres as FCL
primitives), the robot's links from the URDF's collision meshes as exact triangle
meshes (FCL BVH models, not hulls), its forward kinematics from the URDF with numpy,
and checks every path at most `--step` rad apart (max over joints): robot against
the scene, and link pairs the scene's allowed-collision matrix does not allow.
Nothing here uses tabula's code.

    pip install python-fcl trimesh pyyaml numpy
    python3 scripts/mbm_check_paths.py --urdf data/mbm/panda/panda.urdf \
        --problems ../shared/mbm/panda/problems.tar.bz2 --paths /tmp/paths.json
"""
import argparse, io, json, os, re, sys, tarfile
import xml.etree.ElementTree as ET
import numpy as np
import fcl, trimesh, yaml


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def transform(xyz, R):
    T = np.eye(4); T[:3, :3] = R; T[:3, 3] = xyz; return T


def origin(el):
    o = el.find('origin')
    xyz = [float(v) for v in (o.get('xyz', '0 0 0') if o is not None else '0 0 0').split()]
    rpy = [float(v) for v in (o.get('rpy', '0 0 0') if o is not None else '0 0 0').split()]
    return transform(xyz, rpy_matrix(*rpy))


def axis_angle(axis, a):
    axis = np.asarray(axis) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def quat_matrix(q):
    x, y, z, w = q
    n = np.sqrt(x * x + y * y + z * z + w * w); x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class Robot:
    def __init__(self, urdf):
        root = ET.parse(urdf).getroot()
        base = os.path.dirname(os.path.abspath(urdf))
        self.joints = {}
        children = set()
        for j in root.findall('joint'):
            ax = j.find('axis')
            self.joints[j.find('child').get('link')] = dict(
                name=j.get('name'), type=j.get('type'), parent=j.find('parent').get('link'),
                origin=origin(j), axis=[float(v) for v in (ax.get('xyz') if ax is not None else '1 0 0').split()])
            children.add(j.find('child').get('link'))
        self.links = {}
        for l in root.findall('link'):
            shapes = []
            for c in l.findall('collision'):
                m = c.find('geometry/mesh')
                if m is None:
                    continue
                path = re.sub(r'^package://', '', m.get('filename'))
                mesh = trimesh.load(os.path.join(base, path), force='mesh')
                bvh = fcl.BVHModel(); bvh.beginModel(len(mesh.vertices), len(mesh.faces))
                bvh.addSubModel(mesh.vertices, mesh.faces); bvh.endModel()
                shapes.append((bvh, origin(c)))
            self.links[l.get('name')] = shapes
        self.root = next(n for n in self.links if n not in children)

    def fk(self, q):
        memo = {self.root: np.eye(4)}
        def pose(link):
            if link not in memo:
                j = self.joints[link]
                T = pose(j['parent']) @ j['origin']
                if j['type'] in ('revolute', 'continuous'):
                    T = T @ transform([0, 0, 0], axis_angle(j['axis'], q.get(j['name'], 0.0)))
                elif j['type'] == 'prismatic':
                    T = T @ transform(np.asarray(j['axis']) * q.get(j['name'], 0.0), np.eye(3))
                memo[link] = T
            return memo[link]
        return {l: pose(l) for l in self.links}


def fcl_object(geom, T):
    return fcl.CollisionObject(geom, fcl.Transform(T[:3, :3], T[:3, 3]))


def vec(v, keys):
    return [float(v[k]) for k in keys] if isinstance(v, dict) else [float(x) for x in v]


def scene_objects(scene):
    out = []
    for o in (scene.get('world') or {}).get('collision_objects') or []:
        # MoveIt (and VAMP's loader): primitive poses are relative to the object's pose.
        base = np.eye(4)
        if o.get('pose'):
            bp = o['pose']
            base = transform(vec(bp.get('position', [0, 0, 0]), 'xyz'),
                             quat_matrix(vec(bp.get('orientation', [0, 0, 0, 1]), 'xyzw')))
        for prim, p in zip(o.get('primitives') or [], o.get('primitive_poses') or []):
            kind = prim['type']; d = prim['dimensions']
            kind = {1: 'box', 2: 'sphere', 3: 'cylinder'}.get(kind, kind)
            geom = {'box': lambda: fcl.Box(*d), 'sphere': lambda: fcl.Sphere(d[0]),
                    'cylinder': lambda: fcl.Cylinder(d[1], d[0])}[kind]()
            T = transform(vec(p.get('position', [0, 0, 0]), 'xyz'),
                          quat_matrix(vec(p.get('orientation', [0, 0, 0, 1]), 'xyzw')))
            out.append((o['id'], fcl_object(geom, base @ T)))
    return out


def allowed(scene):
    acm = scene.get('allowed_collision_matrix') or {}
    names = acm.get('entry_names') or []
    ok = set()
    for i, row in enumerate(acm.get('entry_values') or []):
        row = row.get('enabled', row) if isinstance(row, dict) else row
        for k, v in enumerate(row):
            if v:
                ok.add((names[i], names[k])); ok.add((names[k], names[i]))
    return ok


def problems(path):
    files = {}
    if os.path.isdir(path):
        for dirpath, _, names in os.walk(path):
            for n in names:
                files[(os.path.basename(dirpath), n)] = lambda p=os.path.join(dirpath, n): open(p).read()
    else:
        tar = tarfile.open(path)
        for m in tar.getmembers():
            if m.isfile():
                parts = m.name.split('/')
                files[(parts[-2] if len(parts) > 1 else '', parts[-1])] = lambda m=m: tar.extractfile(m).read().decode()
    return files


def main():
    a = argparse.ArgumentParser()
    a.add_argument('--urdf', required=True); a.add_argument('--problems', required=True)
    a.add_argument('--paths', required=True); a.add_argument('--step', type=float, default=0.01)
    args = a.parse_args()
    robot = Robot(args.urdf)
    files = problems(args.problems)
    rows = json.load(open(args.paths))
    touching, configurations = [], 0
    request = fcl.CollisionRequest()
    for row in rows:
        scene = yaml.safe_load(files[(row['set'], 'scene%04d.yaml' % row['index'])]())
        obstacles = scene_objects(scene)
        ok = allowed(scene)
        moving = [l for l, s in robot.links.items() if s]
        pairs = [(x, y) for i, x in enumerate(moving) for y in moving[i + 1:] if (x, y) not in ok]
        state = scene.get('robot_state', {}).get('joint_state', {})
        fixed = dict(zip(state.get('name', []), state.get('position', [])))
        hit = None
        path = [np.asarray(p) for p in row['path']]
        for qa, qb in zip(path, path[1:]):
            n = max(1, int(np.ceil(np.max(np.abs(qb - qa)) / args.step)))
            for k in range(n + 1):
                q = dict(fixed); q.update(zip(row['joint_names'], qa + (qb - qa) * k / n))
                poses = robot.fk(q); configurations += 1
                placed = {l: [fcl_object(g, poses[l] @ T) for g, T in robot.links[l]] for l in moving}
                for l in moving:
                    for body in placed[l]:
                        for name, o in obstacles:
                            if fcl.collide(body, o, request, fcl.CollisionResult()):
                                hit = (l, name); break
                        if hit: break
                    if hit: break
                for x, y in ([] if hit else pairs):
                    if any(fcl.collide(u, v, request, fcl.CollisionResult()) for u in placed[x] for v in placed[y]):
                        hit = (x, y); break
                if hit: break
            if hit: break
        if hit:
            touching.append((row['set'], row['index'], hit))
    print(json.dumps({'paths': len(rows), 'configurations_checked': configurations,
                      'step_rad': args.step, 'touching': len(touching), 'touching_paths': touching[:50]}))


if __name__ == '__main__':
    sys.exit(main())
