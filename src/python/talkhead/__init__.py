# SPDX-License-Identifier: GPL-3.0-or-later
"""talkhead: talking-head videos from timed speech, in Python (issue 33, decision D63).

Every function runs talkhead's own command in process (the same code as the ``talkhead`` executable, so the
same files, frames and messages), with the GIL released while it works::

    import talkhead
    talkhead.render("out.mp4", transcript="s.TextGrid", audio="s.wav", emotion="joy:0.6")
    for t, image in talkhead.frames(transcript="s.TextGrid", lang="en-US"):   # numpy H×W×3 uint8 (RGB)
        ...
    talkhead.say("Hello there.", "hello.mp4", lang="en-US")
    talkhead.say("Hello there.", "real.mp4", lang="en-US", face="grid-s4")   # a real face that ships (`talkhead faces`)
    talkhead.visemes("s.TextGrid", lang="en-US")   # [{'start': 0.0, 'end': 0.12, 'phone': '_', 'cdv': 'sil', ...}, ...]

Keyword options are the command's fields — its long options by name: ``head_motion="off"`` is the field
``head-motion`` (``--head-motion off``); ``True`` is a switch, ``None`` and ``False`` leave it out, a list
repeats it. The keywords become a job (``talkhead job``'s JSON, which batch hands its children too) and the
command runs it. Errors raise ``talkhead.Error`` (``talkhead.UsageError`` for options the command refuses)
with the command line's message.
"""
import json
import os
import tempfile
from pathlib import Path

from ._talkhead import Error, FrameStream, UsageError, run as _run, run_job as _run_job

__all__ = ["Error", "UsageError", "run", "render", "frames", "say", "visemes", "build", "batch", "Model"]


def _installed_data():
    # Installed by `cmake --install`: <prefix>/lib/python3*/dist-packages/talkhead → <prefix>/share/talkhead.
    here = Path(__file__).resolve()
    for up in here.parents:
        share = up / "share" / "talkhead"
        if (share / "phonetics").is_dir():
            os.environ.setdefault("TALKHEAD_DATA_DIR", str(share))
            if (share / "models" / "default.thm").is_file():
                os.environ.setdefault("TALKHEAD_MODEL", str(share / "models" / "default.thm"))
            plugins = up / "lib" / "talkhead"  # libav, OpenImageIO and dlib load from here on first use
            if (plugins / "libtalkhead-av.so").is_file():
                os.environ.setdefault("TALKHEAD_MODULE_DIR", str(plugins))
            return


_installed_data()


def _job(command, *named, **options):
    """A job (JSON: the command and its fields, as `talkhead job` reads it) from keyword pairs in order."""
    fields = {}
    for key, value in [*named, *options.items()]:
        if isinstance(value, Model):
            value = value.path
        if value is None or value is False:
            continue
        values = [v for v in (value if isinstance(value, (list, tuple)) else [value]) if v is not None and v is not False]
        values = [True if v is True else os.fspath(v) if isinstance(v, os.PathLike) else str(v) for v in values]
        if values:
            fields[key.replace("_", "-")] = values if isinstance(value, (list, tuple)) else values[0]
    return json.dumps({"command": command, "fields": fields})


def run(*args, progress=None):
    """Runs a talkhead command: ``run("render", "--transcript", "s.TextGrid", "-o", "out.mp4")``.

    ``progress(done, total)`` is called after each frame a render draws; an exception it raises stops the
    render (no partial output) and propagates."""
    _run([os.fspath(a) for a in args], progress)


class Model:
    """A face model file (``talkhead build`` writes one; None: the default face). Pass it as ``model=``."""

    def __init__(self, path=None):
        self.path = None if path is None else os.fspath(path)
        if self.path is not None and not os.path.isfile(self.path):
            raise Error(f"{self.path}: no such model file")

    def __repr__(self):
        return f"talkhead.Model({self.path!r})"


def _video_job(transcript, audio, text, emotion, controls, model, face, lang, options, *extra):
    return _job("render", ("transcript", transcript), ("text", text), ("audio", audio), ("emotion", emotion), ("controls", controls),
                ("model", model), ("face", face), ("lang", lang), *options.items(), *extra)


def render(output, *, transcript=None, audio=None, text=None, emotion=None, controls=None, model=None, face=None, lang=None, progress=None,
           **options):
    """Renders a video (``talkhead render``): MP4 by default, y4m with ``format="y4m"``. ``face="grid-s4"``
    names a face that ships with talkhead (``talkhead faces``; built on first use), ``model=`` a model file.
    The speech: ``transcript=`` (with ``audio=``), ``audio=`` with ``text=`` (aligned), or ``audio=`` alone
    (its phones recognised from the sound)."""
    _run_job(_video_job(transcript, audio, text, emotion, controls, model, face, lang, options, ("output", output)), progress)


def frames(*, transcript=None, audio=None, text=None, emotion=None, controls=None, model=None, face=None, lang=None, **options):
    """The frames a render draws, as ``(seconds, image)`` pairs in order: ``image`` is a numpy array of
    shape (height, width, 3), uint8 RGB, equal byte for byte to the PNGs of ``render --frames``; with
    ``background="transparent"``, (height, width, 4) RGBA, the face's matte as alpha. Frames are drawn a few
    ahead on another thread; leaving the loop stops the render."""
    stream = FrameStream.of_job(_video_job(transcript, audio, text, emotion, controls, model, face, lang, options, ("format", "none"), ("quiet", True)))
    try:
        for _, seconds, image in stream:
            yield seconds, image
    finally:
        stream.close()


def say(text, output=None, *, lang=None, emotion=None, voice=None, model=None, face=None, progress=None, **options):
    """Speaks text with espeak-ng and renders the face saying it (``talkhead say``); ``face=`` as render's."""
    _run_job(_job("say", ("text", text), ("lang", lang), ("emotion", emotion), ("voice", voice), ("model", model), ("face", face), ("output", output),
                  *options.items()), progress)


def visemes(transcript=None, *, audio=None, lang=None, **options):
    """The phones of a timed transcript with their visemes and keyposes, as a list of dicts
    (``talkhead visemes --out-format json``): start, end, phone, cdv, keypose (seconds). With ``audio=``
    instead of a transcript, the phones recognised from the sound, each with its confidence."""
    if (transcript is None) == (audio is None):
        raise Error("visemes: give a transcript or audio=, one of them")
    with tempfile.TemporaryDirectory(prefix="talkhead-") as d:
        out = os.path.join(d, "visemes.json")
        _run_job(_job("visemes", ("transcript", transcript), ("audio", audio), ("out-format", "json"), ("output", out), ("lang", lang),
                      *options.items()))
        with open(out, encoding="utf-8") as f:
            data = json.load(f)
    return data["phones"] if isinstance(data, dict) and "phones" in data else data


def build(corpus, output, **options):
    """Builds a face model from a corpus (``talkhead build``); returns it as a Model."""
    _run_job(_job("build", ("corpus", corpus), ("output", output), *options.items()))
    return Model(output)


def batch(manifest, output, **options):
    """Renders a stimulus batch from a manifest (``talkhead batch``) into the folder ``output``."""
    _run_job(_job("batch", ("manifest", manifest), ("output", output), *options.items()))
