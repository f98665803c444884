#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# A PsychoPy-style experiment loop over talkhead's frame iterator: for each stimulus of a list (a timed
# transcript and an emotion), the frames are shown at their own timestamps and each onset is logged.
# With PsychoPy installed the frames go to a window (ImageStim); without it (or with --headless) the loop
# runs the same way without drawing, so the script is testable on a server.
#   PYTHONPATH=build/python examples/python/stimulus_list.py [--headless] [LOG.tsv]
import csv
import sys
import time
from pathlib import Path

import talkhead

ROOT = Path(__file__).resolve().parents[2]
STIMULI = [  # (id, transcript, emotion): in an experiment, read these from the trial list
    ("s1", ROOT / "examples" / "que_noticia.TextGrid", "joy"),
    ("s2", ROOT / "examples" / "que_noticia.TextGrid", "distress:0.7"),
    ("s3", ROOT / "examples" / "que_noticia.TextGrid", "neutral"),
]


def window():
    if "--headless" in sys.argv:
        return None
    try:
        from psychopy import visual  # noqa: F401  (optional)
    except ImportError:
        return None
    return visual.Window(size=(640, 360), units="pix", color="black")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    log_path = Path(args[0]) if args else Path("onsets.tsv")
    win = window()
    with open(log_path, "w", newline="") as f:
        log = csv.writer(f, delimiter="\t")
        log.writerow(["stimulus", "emotion", "frame", "video_time", "onset_clock"])
        clock0 = time.perf_counter()
        for sid, transcript, emotion in STIMULI:
            start = None  # the onset: when frame 0 is shown; every later frame at onset + its own time
            for n, (t, image) in enumerate(talkhead.frames(transcript=transcript, emotion=emotion, size="640x360", fps=30)):
                if start is None:
                    start = time.perf_counter() - t
                # Wait for the frame's own time (a real experiment flips on the screen's refresh instead).
                delay = start + t - time.perf_counter()
                if delay > 0:
                    time.sleep(delay)
                if win is not None:
                    from psychopy import visual
                    visual.ImageStim(win, image=image[::-1] / 127.5 - 1, size=image.shape[1::-1]).draw()
                    win.flip()
                if n == 0:
                    log.writerow([sid, emotion, n, f"{t:.4f}", f"{time.perf_counter() - clock0:.4f}"])
    print(f"{len(STIMULI)} stimuli shown; onsets in {log_path}")


if __name__ == "__main__":
    main()
