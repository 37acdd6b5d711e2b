"""Times SnapPy's inside view, for issue #19's comparison (BENCHMARKS.md,
"Against SnapPy's inside view"). Not part of the tests: SnapPy is not a
dependency of this project.

    python3 -m venv /tmp/snappy-venv && /tmp/snappy-venv/bin/pip install snappy==3.3.2
    LIBGL_ALWAYS_SOFTWARE=1 LP_NUM_THREADS=2 xvfb-run -a -s "-screen 0 1280x1024x24" \
        /tmp/snappy-venv/bin/python crates/bevy_manifold_bench/snappy_time.py "m003(-3,1)" 640 360 5

SnapPy's own RaytracingView (through its InsideViewer, the window
`Manifold.inside_view()` opens) renders its plain scene with 100 ray
steps to distance 17; each timed frame is `render_to_array`, which draws
into an off-screen framebuffer and reads the image back, after three
untimed frames (shader compilation).
"""

import sys
import time
import tkinter

import snappy
from snappy.raytracing.inside_viewer import InsideViewer

name, width, height, frames = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
root = tkinter.Tk()
viewer = InsideViewer(root, snappy.Manifold(name))
viewer.pack()
widget = viewer.widget
widget.ui_uniform_dict["maxSteps"][1] = 100
widget.ui_uniform_dict["maxDist"][1] = 17.0
root.update()
for _ in range(3):
    widget.render_to_array(width, height)
times = []
for _ in range(frames):
    start = time.perf_counter()
    widget.render_to_array(width, height)
    times.append(time.perf_counter() - start)
times.sort()
print(
    f"snappy {snappy.__version__} {name} {width}x{height}, 100 steps, distance 17: "
    f"best {times[0] * 1e3:.1f} ms, median {times[len(times) // 2] * 1e3:.1f} ms of {frames}"
)
root.destroy()
