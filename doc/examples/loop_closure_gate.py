#!/usr/bin/env python3
"""Template: a SLAM back end that asks CorAl before it adds a loop-closure edge.

Copy LoopClosureBackEnd.on_loop_candidate into your back end's loop-closure callback: after
your matcher (ICP, GICP, ...) registered keyframe b against keyframe a, it sends both clouds
and T_a_b to the `check_alignment` service of a running coral_node / CoralNodelet with
loop_closure=True and adds the edge only on an aligned verdict.

Demo (coral_node running, e.g. `rosrun coral_introspection coral_node` with a preset loaded):
  loop_closure_gate.py --a 000109.pcd --b 000161.pcd --transform_file T.txt
prints `edge added` or `edge rejected: <why>` and exits 0 (2 on bad arguments or input).
"""
import argparse
import sys

import numpy as np
import rospy
from geometry_msgs.msg import Quaternion, Transform, Vector3
from sensor_msgs import point_cloud2
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

    def on_loop_candidate(self, cloud_a, cloud_b, T_a_b):
        """cloud_a, cloud_b: sensor_msgs/PointCloud2 in their own sensor frames; T_a_b: 4x4
        numpy array mapping points of b into a's frame (p_a = T_a_b p_b), from your matcher.
        Returns True when the edge was added."""
        req = CheckAlignmentRequest(cloud_a=cloud_a, cloud_b=cloud_b,
                                    transform_a_b=to_transform_msg(T_a_b),
                                    loop_closure=True)  # judged with the loop_closure/ gate
        try:
            # rospy has no per-call timeout: bound the wait for the service instead.
            rospy.wait_for_service(self.service, timeout=self.timeout)
            res = self.check(req)
        except (rospy.ROSException, rospy.ServiceException) as e:
            # No verdict: do not add an unchecked loop (a wrong loop ruins the whole graph).
            return self._reject("service %s unavailable: %s" % (self.service, e))
        r = res.result
        if r.valid and r.aligned:
            self.edges.append((cloud_a.header.frame_id, cloud_b.header.frame_id, T_a_b))
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


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--a", required=True, help="keyframe a (.pcd)")
    p.add_argument("--b", required=True, help="keyframe b (.pcd)")
    p.add_argument("--transform_file", required=True, help="4x4 or 3x4 row-major T_a_b")
    p.add_argument("--service", default="check_alignment")
    args = p.parse_args(rospy.myargv()[1:])
    rospy.init_node("loop_closure_gate", anonymous=True)
    try:
        T = np.eye(4)
        T[:3, :] = np.loadtxt(args.transform_file).reshape(-1, 4)[:3]
        stamp = rospy.Time.now()
        cloud_a = point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="keyframe_a"),
                                                  read_pcd_xyz(args.a))
        cloud_b = point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="keyframe_b"),
                                                  read_pcd_xyz(args.b))
    except (OSError, ValueError, KeyError) as e:
        print("loop_closure_gate: %s" % e, file=sys.stderr)
        return 2
    back_end = LoopClosureBackEnd(args.service)
    if back_end.on_loop_candidate(cloud_a, cloud_b, T):
        print("edge added")
    else:
        print("edge rejected: %s" % back_end.last_rejection)
    return 0


if __name__ == "__main__":
    sys.exit(main())
