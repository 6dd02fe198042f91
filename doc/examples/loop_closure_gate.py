#!/usr/bin/env python3
"""Template: a SLAM back end that asks CorAl before it adds a loop-closure edge.

Copy LoopClosureBackEnd.on_loop_candidate into your back end's loop-closure callback: after
your matcher (ICP, GICP, ...) registered keyframe b against keyframe a, it sends both scans
(sensor_msgs/PointCloud2, or sensor_msgs/LaserScan for a 2D back end such as slam_karto) and
T_a_b to the `check_alignment` service of a running coral_node / CoralNodelet with
loop_closure=True and adds the edge only on an aligned verdict.

Demo (coral_node running, e.g. `rosrun coral_introspection coral_node` with a preset loaded):
  loop_closure_gate.py --a 000109.pcd --b 000161.pcd --transform_file T.txt
prints `edge added` or `edge rejected: <why>` and exits 0 (2 on bad arguments or input).
With --laser_scan the two files are planar scans (z = 0, in the scanner's frame) sent as the
LaserScans of their readings, to a node with config/lidar_2d.yaml and input_type laser_scan.
"""
import argparse
import sys

import numpy as np
import rospy
from geometry_msgs.msg import Quaternion, Transform, Vector3
from sensor_msgs import point_cloud2
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Header

from coral_introspection.srv import CheckAlignment, CheckAlignmentRequest


class LoopClosureBackEnd:
    """Minimal back end: a list of edges (a, b, T_a_b); yours would be a pose graph."""

    def __init__(self, service="check_alignment", timeout=10.0):
        self.service = service
        self.timeout = timeout  # [s] to wait for the service
        self.check = rospy.ServiceProxy(service, CheckAlignment)
        self.edges = []
        self.last_rejection = ""

    def on_loop_candidate(self, scan_a, scan_b, T_a_b):
        """scan_a, scan_b: two sensor_msgs/PointCloud2 or two sensor_msgs/LaserScan, each in
        its own sensor frame; T_a_b: 4x4 numpy array mapping points of b into a's frame
        (p_a = T_a_b p_b), from your matcher. Returns True when the edge was added."""
        # LaserScans go in scan_a / scan_b (a node with input_type laser_scan), clouds in
        # cloud_a / cloud_b; a request holding both kinds is refused.
        fields = ("scan_a", "scan_b") if isinstance(scan_a, LaserScan) else ("cloud_a", "cloud_b")
        req = CheckAlignmentRequest(transform_a_b=to_transform_msg(T_a_b),
                                    loop_closure=True)  # judged with the loop_closure/ gate
        setattr(req, fields[0], scan_a)
        setattr(req, fields[1], scan_b)
        try:
            # rospy has no per-call timeout: bound the wait for the service instead.
            rospy.wait_for_service(self.service, timeout=self.timeout)
            res = self.check(req)
        except (rospy.ROSException, rospy.ServiceException) as e:
            # No verdict: do not add an unchecked loop (a wrong loop ruins the whole graph).
            return self._reject("service %s unavailable: %s" % (self.service, e))
        r = res.result
        if r.valid and r.aligned:
            self.edges.append((scan_a.header.frame_id, scan_b.header.frame_id, T_a_b))
            return True
        # Judged and misaligned: rejected_by names the term that said so. With correction_hint
        # "refined" (loop_closure/max_refinement or restarts) the pose transform_a_b * correction
        # passes: register again from there with your matcher and ask again, rather than adding it
        # as is.
        if r.valid:
            return self._reject(r.rejected_by)
        # No verdict (refused request, too little overlap, ...): reason / error say why.
        return self._reject(r.reason or res.error)

    def _reject(self, why):
        self.last_rejection = why
        rospy.logwarn("loop closure rejected: %s", why)
        return False


def to_transform_msg(T):
    """4x4 homogeneous matrix -> geometry_msgs/Transform (unit quaternion)."""
    R = np.asarray(T[:3, :3], dtype=float)
    # Shepperd's method on the largest diagonal term of the quaternion's outer product.
    K = np.array([[1 + R[0, 0] - R[1, 1] - R[2, 2], R[0, 1] + R[1, 0], R[0, 2] + R[2, 0], R[2, 1] - R[1, 2]],
                  [R[0, 1] + R[1, 0], 1 - R[0, 0] + R[1, 1] - R[2, 2], R[1, 2] + R[2, 1], R[0, 2] - R[2, 0]],
                  [R[0, 2] + R[2, 0], R[1, 2] + R[2, 1], 1 - R[0, 0] - R[1, 1] + R[2, 2], R[1, 0] - R[0, 1]],
                  [R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1], 1 + R[0, 0] + R[1, 1] + R[2, 2]]])
    q = K[np.argmax(np.diag(K))]
    q /= np.linalg.norm(q)  # (x, y, z, w)
    return Transform(translation=Vector3(*T[:3, 3]), rotation=Quaternion(*q))


def read_pcd_xyz(path):
    """x y z of a PCD file (DATA ascii or binary, any numeric fields) as an N x 3 array."""
    header = {}
    with open(path, "rb") as f:
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            if not line:
                raise ValueError("%s: no DATA line" % path)
            if line.startswith("#"):
                continue
            key, _, value = line.partition(" ")
            header[key] = value.split()
            if key == "DATA":
                break
        body = f.read()
    names, n = header["FIELDS"], int(header["POINTS"][0])
    counts = [int(c) for c in header.get("COUNT", ["1"] * len(names))]
    kinds = {"F": "f", "I": "i", "U": "u"}
    dtype = np.dtype([(nm, "<%s%s" % (kinds[t], s), (c,)) for nm, t, s, c
                      in zip(names, header["TYPE"], header["SIZE"], counts)])
    if header["DATA"][0] == "binary":
        data = np.frombuffer(body, dtype=dtype, count=n)
    elif header["DATA"][0] == "ascii":
        data = np.loadtxt(body.decode().splitlines(), dtype=dtype, ndmin=1)
    else:
        raise ValueError("%s: DATA %s not supported" % (path, header["DATA"][0]))
    return np.stack([data[c][:, 0] for c in "xyz"], axis=1).astype(np.float32)


def laser_scan_from_planar(xyz, header):
    """The sensor_msgs/LaserScan of planar points in the scanner's frame (z ignored): bearings
    at the median step between the sorted bearings, beams without a point written as inf (no
    return), range_max above the farthest point. A 2D back end holds its LaserScans already;
    this only rebuilds them from the demo's files."""
    bearing = np.arctan2(xyz[:, 1], xyz[:, 0]).astype(float)
    ranges = np.hypot(xyz[:, 0], xyz[:, 1]).astype(float)
    order = np.argsort(bearing)
    bearing, ranges = bearing[order], ranges[order]
    steps = np.diff(bearing)
    steps = steps[steps > 1e-6]
    if len(steps) == 0:
        raise ValueError("fewer than two distinct bearings: not a planar scan")
    inc = float(np.median(steps))
    index = np.rint((bearing - bearing[0]) / inc).astype(int)
    readings = np.full(index[-1] + 1, np.inf)
    readings[index] = ranges
    return LaserScan(header=header, angle_min=bearing[0], angle_max=bearing[0] + index[-1] * inc,
                     angle_increment=inc, range_min=0.0, range_max=float(ranges.max()) + 1.0,
                     ranges=readings.tolist())


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--a", required=True, help="keyframe a (.pcd)")
    p.add_argument("--b", required=True, help="keyframe b (.pcd)")
    p.add_argument("--transform_file", required=True, help="4x4 or 3x4 row-major T_a_b")
    p.add_argument("--service", default="check_alignment")
    p.add_argument("--laser_scan", action="store_true",
                   help="send the (planar) files as sensor_msgs/LaserScan")
    args = p.parse_args(rospy.myargv()[1:])
    rospy.init_node("loop_closure_gate", anonymous=True)
    try:
        T = np.eye(4)
        T[:3, :] = np.loadtxt(args.transform_file).reshape(-1, 4)[:3]
        stamp = rospy.Time.now()
        to_msg = laser_scan_from_planar if args.laser_scan else \
            lambda xyz, h: point_cloud2.create_cloud_xyz32(h, xyz)
        scan_a = to_msg(read_pcd_xyz(args.a), Header(stamp=stamp, frame_id="keyframe_a"))
        scan_b = to_msg(read_pcd_xyz(args.b), Header(stamp=stamp, frame_id="keyframe_b"))
    except (OSError, ValueError, KeyError) as e:
        print("loop_closure_gate: %s" % e, file=sys.stderr)
        return 2
    back_end = LoopClosureBackEnd(args.service)
    if back_end.on_loop_candidate(scan_a, scan_b, T):
        print("edge added")
    else:
        print("edge rejected: %s" % back_end.last_rejection)
    return 0


if __name__ == "__main__":
    sys.exit(main())
