#!/usr/bin/env python3
"""Elevation of the TI radar's points in the shared bag (doc/rio.md, "Elevation uncertainty of
a one-baseline radar"): how sin(elevation) is quantised, and the angular noise that the Doppler
residuals of the moving part show.

  scripts/experiments/rio_elevation_stats.py --bag ../shared/data/ti_mmwave_demo/ti_mmwave_rospkg_demo.bag

1. Every point (range >= 0.25 m): the distinct values of z / r = sin(elevation) and their
   step.
2. Moving part (--moving, bag seconds; radar speed above 0.5 m/s): the points in the front
   end's field of view (+-60 deg, config/rio_ti_mmwave.yaml), per frame a least-squares radar
   velocity from the sign-normalised Doppler m = d^T v (iteratively trimmed at --trim robust
   sigmas, or at a fixed m/s value with --trim-abs), then the squared inlier residuals
   (scaled by n / (n - 3)) regressed on (e_el^T v)^2 and (e_az^T v)^2:
     E[res^2] = sigma_doppler^2 + sigma_el^2 (e_el^T v)^2 + sigma_az^2 (e_az^T v)^2,
   the Doppler variance of Eq. 10-12 (cos(el) folded into e_az). The per-frame fit absorbs
   any error common to a frame's points (a common elevation error is nearly collinear with
   the vertical velocity), so the sigmas are of the part independent from point to point.
"""
import argparse

import numpy as np
import rosbag
import sensor_msgs.point_cloud2 as pc2


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bag", required=True)
    ap.add_argument("--topic", default="/ti_mmwave/radar_scan_pcl")
    ap.add_argument("--moving", type=float, nargs=2, default=[13.7, 33.3],
                    help="[s] from the first scan: the moving part")
    ap.add_argument("--trim", type=float, default=3.0, help="robust sigmas of the trimming")
    ap.add_argument("--trim-abs", type=float, default=0.0,
                    help="[m/s] fixed trimming threshold instead of --trim")
    ap.add_argument("--fov", type=float, default=1.047, help="[rad] |azimuth|, |elevation|")
    args = ap.parse_args()

    sines, frames, t0 = [], [], None
    for _, msg, stamp in rosbag.Bag(args.bag).read_messages(topics=[args.topic]):
        t = stamp.to_sec()
        t0 = t if t0 is None else t0
        pts = []
        for x, y, z, vr in pc2.read_points(msg, field_names=("x", "y", "z", "velocity"),
                                           skip_nans=True):
            r = np.sqrt(x * x + y * y + z * z)
            if r < 0.25:
                continue
            sines.append(z / r)
            az, el = np.arctan2(y, x), np.arcsin(z / r)
            if abs(az) <= args.fov and abs(el) <= args.fov:
                pts.append((az, el, -vr))  # m = -v_r: v_r is positive away from the sensor
        if args.moving[0] < t - t0 < args.moving[1] and len(pts) >= 10:
            frames.append(np.array(pts))

    s = np.unique(np.round(np.array(sines), 6))
    steps = np.unique(np.round(np.diff(s), 6))
    print("points: %d; sin(elevation) takes %d values from %.5f to %.5f, steps %s"
          % (len(sines), len(s), s[0], s[-1], ", ".join("%.5f" % d for d in steps)))
    el = np.degrees(np.arcsin(np.array(sines)))
    print("elevation [deg]: mean %.1f, 5 / 50 / 95 %%: %.1f / %.1f / %.1f"
          % (el.mean(), *np.percentile(el, [5, 50, 95])))

    res2, a_el, a_az, used = [], [], [], 0
    for f in frames:
        az, el, m = f[:, 0], f[:, 1], f[:, 2]
        d = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], 1)
        keep = np.ones(len(m), bool)
        for _ in range(4):
            v = np.linalg.lstsq(d[keep], m[keep], rcond=None)[0]
            res = d @ v - m
            thr = args.trim_abs or args.trim * max(1.4826 * np.median(np.abs(res[keep])), 0.03)
            keep = np.abs(res) < thr
        if keep.sum() < 8 or np.linalg.norm(v) < 0.5:
            continue
        used += 1
        e_el = np.stack([-np.sin(el) * np.cos(az), -np.sin(el) * np.sin(az), np.cos(el)], 1)
        e_az = np.stack([-np.sin(az), np.cos(az), 0 * az], 1)
        n = keep.sum()
        res2 += list(res[keep] ** 2 * n / (n - 3))
        a_el += list((e_el[keep] @ v) ** 2)
        a_az += list((e_az[keep] @ v) ** 2)
    X = np.stack([np.ones(len(a_el)), a_el, a_az], 1)
    c = np.linalg.lstsq(X, np.array(res2), rcond=None)[0]
    sig = np.sqrt(np.maximum(c, 0.0))
    print("moving part: %d frames, %d inlier residuals (trim %s)"
          % (used, len(res2), "%g m/s" % args.trim_abs if args.trim_abs else
             "%g robust sigmas" % args.trim))
    print("Doppler residuals: sigma_doppler %.3f m/s, sigma_el %.3f rad, sigma_az %.3f rad"
          % tuple(sig))


if __name__ == "__main__":
    main()
