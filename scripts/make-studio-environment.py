#!/usr/bin/env python3
"""Writes scenes/examples/studio.pfm: a synthetic photographic studio as a latitude-longitude map.

Not a measurement: a dark cyclorama (linear grey 0.04 below the horizon, rising to 0.25 overhead),
two large softboxes left and right of the camera's line of sight and a strip light overhead, each a
uniform white emitter of radiance `scale` relative to the D65 white of the renderer
(RGB (1, 1, 1) = D65 at Y = 1). Layout as in docs/scene-format.md: the top row looks straight up
(+y), the image centre along -z, columns run from -z towards +x. Deterministic, no inputs.

    python3 scripts/make-studio-environment.py [OUT.pfm]
"""
import math
import struct
import sys

W, H = 256, 128


def box(phi_deg, theta_deg, phi0, phi1, th0, th1):
    """1 inside the angular rectangle [phi0, phi1] x [th0, th1] (degrees), with a 1-degree soft edge."""
    def ramp(x, a, b):
        return max(0.0, min(1.0, x - a + 0.5, b - x + 0.5))
    return ramp(phi_deg, phi0, phi1) * ramp(theta_deg, th0, th1)


def radiance(phi_deg, theta_deg):
    """phi: azimuth from -z towards +x in degrees (-180..180); theta: angle from +y (0..180)."""
    elevation = 90.0 - theta_deg
    if elevation < 0.0:
        grey = 0.04
    else:
        grey = 0.04 + 0.21 * math.sin(math.radians(elevation))
    # Key softbox front-left, fill softbox front-right (seen from a camera on +z looking at -z, "front"
    # is behind the camera: phi near +-180), strip light overhead running front to back.
    light = (9.0 * box(phi_deg, theta_deg, 120.0, 160.0, 40.0, 80.0)
             + 4.0 * box(phi_deg, theta_deg, -150.0, -115.0, 45.0, 80.0)
             + 6.0 * box(phi_deg, theta_deg, -100.0, 100.0, 4.0, 12.0))
    v = grey + light
    return (v, v, v)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/examples/studio.pfm"
    rows = []
    for j in range(H):  # j = 0 is the top row (straight up)
        theta = 180.0 * (j + 0.5) / H
        row = []
        for i in range(W):
            phi = 360.0 * (i + 0.5) / W - 180.0
            row.extend(radiance(phi, theta))
        rows.append(row)
    with open(out, "wb") as f:
        f.write(f"PF\n{W} {H}\n-1.0\n".encode("ascii"))
        for row in reversed(rows):  # PFM stores the bottom row first
            f.write(struct.pack(f"<{len(row)}f", *row))


if __name__ == "__main__":
    main()
