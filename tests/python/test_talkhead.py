# SPDX-License-Identifier: GPL-3.0-or-later
# The talkhead Python module (issue 33): real renders through it, frames equal to the CLI's byte for byte
# with their timestamps, errors as exceptions with the CLI's messages, progress, the GIL released.
# Run by ctest (python.module): PYTHONPATH=build/python, TALKHEAD (the executable) set.
import os
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import talkhead

ROOT = Path(__file__).resolve().parents[2]
TG = ROOT / "examples" / "que_noticia.TextGrid"
TH = os.environ["TALKHEAD"]
SMALL = dict(size="320x180", head_motion="off", blinks="off")


def read_png(path):
    from skimage import io  # python3-skimage (scripts/setup-deps)

    return io.imread(path)


def test_render_writes_the_same_video_as_the_cli(tmp_path):
    talkhead.render(tmp_path / "py.y4m", transcript=TG, emotion="joy:0.6", format="y4m", quiet=True, **SMALL)
    subprocess.run([TH, "render", "--transcript", str(TG), "--emotion", "joy:0.6", "--format", "y4m", "-q", "--size", "320x180",
                    "--head-motion", "off", "--blinks", "off", "-o", str(tmp_path / "cli.y4m")], check=True)
    assert (tmp_path / "py.y4m").read_bytes() == (tmp_path / "cli.y4m").read_bytes()


def test_the_learned_mouth_is_on_by_default_and_off_is_the_thesis_path(tmp_path):
    # Issue 48 (D90): the shipped coarticulation model plans every render unless coarticulation="off".
    talkhead.render(tmp_path / "default.y4m", transcript=TG, format="y4m", quiet=True, **SMALL)
    talkhead.render(tmp_path / "on.y4m", transcript=TG, format="y4m", quiet=True, coarticulation="on", **SMALL)
    talkhead.render(tmp_path / "off.y4m", transcript=TG, format="y4m", quiet=True, coarticulation="off", **SMALL)
    subprocess.run([TH, "render", "--transcript", str(TG), "--format", "y4m", "-q", "--size", "320x180", "--head-motion", "off", "--blinks", "off",
                    "--coarticulation", "off", "--pauses", "natural", "-o", str(tmp_path / "cli-off.y4m")], check=True)
    assert (tmp_path / "default.y4m").read_bytes() == (tmp_path / "on.y4m").read_bytes()
    assert (tmp_path / "off.y4m").read_bytes() == (tmp_path / "cli-off.y4m").read_bytes()
    assert (tmp_path / "default.y4m").read_bytes() != (tmp_path / "off.y4m").read_bytes()


def test_frames_are_the_clis_frames_with_their_times(tmp_path):
    subprocess.run([TH, "render", "--transcript", str(TG), "--fps", "25", "-q", "--size", "320x180", "--head-motion", "off", "--blinks", "off",
                    "--format", "none", "--frames", str(tmp_path / "png")], check=True)
    pngs = sorted((tmp_path / "png").glob("frame_*.png"))
    got = list(talkhead.frames(transcript=TG, fps=25, **SMALL))
    assert len(got) == len(pngs) > 10
    for n, ((seconds, image), png) in enumerate(zip(got, pngs)):
        assert seconds == pytest.approx(n / 25, abs=1e-9)
        assert image.shape == (180, 320, 3) and image.dtype == np.uint8
        assert np.array_equal(image, read_png(png)), png.name


def test_transparent_frames_are_rgba_with_the_clis_matte(tmp_path):
    subprocess.run([TH, "render", "--transcript", str(TG), "-q", "--size", "320x180", "--head-motion", "off", "--blinks", "off",
                    "--format", "none", "--background", "transparent", "--frames", str(tmp_path / "png")], check=True)
    pngs = sorted((tmp_path / "png").glob("frame_*.png"))
    got = list(talkhead.frames(transcript=TG, background="transparent", **SMALL))
    assert len(got) == len(pngs) > 10
    for (seconds, image), png in zip(got[::10], pngs[::10]):
        assert image.shape == (180, 320, 4)
        assert np.array_equal(image, read_png(png)), png.name
    alpha = got[0][1][..., 3]
    assert alpha[0, 0] == 0 and alpha.max() == 255 and ((alpha > 0) & (alpha < 255)).any()


def test_leaving_the_frame_loop_stops_the_render():
    t0 = time.monotonic()
    for n, (seconds, image) in enumerate(talkhead.frames(transcript=TG, **SMALL)):
        if n == 2:
            break
    assert time.monotonic() - t0 < 30


def test_errors_raise_with_the_clis_message(tmp_path):
    with pytest.raises(talkhead.Error, match=r"no-such\.TextGrid"):
        talkhead.render(tmp_path / "x.mp4", transcript=tmp_path / "no-such.TextGrid")
    with pytest.raises(talkhead.UsageError, match="--transcript FILE"):
        talkhead.render(tmp_path / "x.mp4")
    with pytest.raises(talkhead.Error, match="unknown emotion 'glee'"):
        list(talkhead.frames(transcript=TG, emotion="glee"))
    assert issubclass(talkhead.UsageError, talkhead.Error) and issubclass(talkhead.Error, RuntimeError)
    assert not (tmp_path / "x.mp4").exists()


def test_progress_is_called_per_frame_and_an_exception_there_stops_the_render(tmp_path):
    seen = []
    talkhead.render(tmp_path / "p.y4m", transcript=TG, format="y4m", progress=lambda done, total: seen.append((done, total)), **SMALL)
    assert seen and seen[-1][0] == seen[-1][1] and [d for d, _ in seen] == list(range(1, len(seen) + 1))

    def stop(done, total):
        if done == 3:
            raise KeyError("enough")

    with pytest.raises(KeyError, match="enough"):
        talkhead.render(tmp_path / "q.y4m", transcript=TG, format="y4m", progress=stop, **SMALL)
    assert not (tmp_path / "q.y4m").exists()


def test_the_gil_is_released_while_rendering(tmp_path):
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    try:
        talkhead.render(tmp_path / "g.y4m", transcript=TG, format="y4m", fps=60, size="640x360")
    finally:
        done.set()
        t.join()
    assert len(ticks) > 20


def test_say_and_visemes(tmp_path):
    talkhead.say("Bom dia.", tmp_path / "s.y4m", lang="pt-BR", format="y4m", **SMALL)
    assert (tmp_path / "s.y4m").stat().st_size > 100_000
    rows = talkhead.visemes(TG, lang="pt-BR")
    assert rows and {"start", "end", "phone", "cdv"} <= set(rows[0])
    assert rows[0]["start"] == 0 and all(a["end"] == pytest.approx(b["start"]) for a, b in zip(rows, rows[1:]))


def test_a_model_object_and_a_missing_model(tmp_path):
    with pytest.raises(talkhead.Error, match="no such model file"):
        talkhead.Model(tmp_path / "none.thm")
    with pytest.raises(talkhead.Error, match="none.thm"):
        talkhead.render(tmp_path / "m.mp4", transcript=TG, model=tmp_path / "none.thm")


def test_a_shipped_face_by_name(tmp_path, monkeypatch):
    # Issue 48: face= names a face that ships (built on first use into the cache, here a scratch one), as --face.
    # (render from a transcript: `say` in a process that spoke before gets other espeak-ng timings, D51.)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    talkhead.render(tmp_path / "f.y4m", transcript=TG, face="crema-1001", format="y4m", quiet=True, head_motion="off")
    assert b"W480 H360" in (tmp_path / "f.y4m").read_bytes()[:80]
    assert (tmp_path / "cache" / "talkhead" / "models" / "faces" / "crema-1001.thm").is_file()
    subprocess.run([TH, "render", "--transcript", str(TG), "--face", "crema-1001", "--format", "y4m", "-q", "--head-motion", "off",
                    "-o", str(tmp_path / "cli.y4m")], check=True, env={**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")})
    assert (tmp_path / "f.y4m").read_bytes() == (tmp_path / "cli.y4m").read_bytes()
    with pytest.raises(talkhead.Error, match="no face named 'nobody'"):
        talkhead.say("Hello.", tmp_path / "n.y4m", face="nobody", format="y4m")


def test_speech_audio_alone(tmp_path):
    # Issue 49: audio with no timing and no text — its phones recognised, as `visemes --audio` and `render --audio`.
    clip = ROOT / "models" / "faces" / "grid-s4" / "s4hq_pbbc4a.mpg"
    phones = talkhead.visemes(audio=clip)
    spoken = [p for p in phones if p["phone"] != "_"]
    assert len(spoken) >= 10 and all(0 <= p["confidence"] <= 1 for p in phones)
    assert any(p["cdv"] in ("p1", "p2") for p in spoken)
    talkhead.render(tmp_path / "a.y4m", audio=clip, lang="en-US", format="y4m", size="320x180", quiet=True, head_motion="off")
    subprocess.run([TH, "render", "--audio", str(clip), "--lang", "en-US", "--format", "y4m", "--size", "320x180", "-q", "--head-motion", "off",
                    "-o", str(tmp_path / "cli.y4m")], check=True)
    assert (tmp_path / "a.y4m").read_bytes() == (tmp_path / "cli.y4m").read_bytes()
    with pytest.raises(talkhead.Error, match="a transcript or audio="):
        talkhead.visemes()


def test_the_examples_run_headless(tmp_path):
    env = dict(os.environ)
    subprocess.run(["/usr/bin/python3", str(ROOT / "examples" / "python" / "stimulus_list.py"), "--headless", str(tmp_path / "log.tsv")],
                   check=True, env=env, cwd=tmp_path)
    rows = (tmp_path / "log.tsv").read_text().splitlines()
    assert rows[0].split("\t") == ["stimulus", "emotion", "frame", "video_time", "onset_clock"] and len(rows) == 4
    onsets = [float(r.split("\t")[4]) for r in rows[1:]]
    assert onsets == sorted(onsets) and onsets[1] - onsets[0] >= 1.0  # each stimulus shown for its ~1.3 s
    subprocess.run(["/usr/bin/python3", str(ROOT / "examples" / "python" / "tts_pipeline.py"), str(tmp_path / "tts"), "en-US"], check=True, env=env,
                   capture_output=True)
    assert len(list((tmp_path / "tts").glob("sentence*.mp4"))) == 3
    assert json_rows(tmp_path / "tts" / "sentence1.visemes.json")


def json_rows(path):
    import json

    rows = json.loads(path.read_text())
    return rows and all("cdv" in r for r in rows)
