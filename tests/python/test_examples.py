"""examples/python runs headless and draws what it says."""
import runpy

import numpy as np

from conftest import SOURCE_DIR


def test_glass_and_sweep_example(tmp_path):
    example = runpy.run_path(str(SOURCE_DIR / "examples" / "python" / "glass_and_sweep.py"))
    assert len(example["glasses"]()) >= 5
    example["main"](["--out", str(tmp_path), "--resolution", "24", "16", "--spp", "2"])
    for name in ["glass_transmittance.png", "concentration_sweep.png"]:
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    _, images = example["render_sweep"](tmp_path, [0.5, 4.0], (24, 16), 2)
    # More copper sulfate absorbs more red: the cuvette's red falls.
    red = [float(image[..., 0].mean()) for image in images]
    assert red[1] < red[0]
