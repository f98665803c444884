#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# A text-to-speech pipeline step: sentences in, one talking-head video per sentence out, each with the
# visemes it used (for lip-sync checks) beside it. talkhead.say runs espeak-ng in process; a pipeline
# with its own TTS engine would pass its audio and timing file to talkhead.render instead.
#   PYTHONPATH=build/python examples/python/tts_pipeline.py OUTDIR [LANG]
import json
import sys
from pathlib import Path

import talkhead

SENTENCES = ["Good morning.", "The results are ready.", "See you tomorrow."]


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "tts-out")
    lang = sys.argv[2] if len(sys.argv) > 2 else "en-US"
    out.mkdir(parents=True, exist_ok=True)
    for i, text in enumerate(SENTENCES, 1):
        video, words = out / f"sentence{i}.mp4", out / f"sentence{i}.TextGrid"
        talkhead.say(text, video, lang=lang, emotion="joy:0.5", save_transcript=words, quiet=True,
                     progress=lambda done, total: print(f"\r{video.name}: {done}/{total}", end="", flush=True))
        print()
        (out / f"sentence{i}.visemes.json").write_text(json.dumps(talkhead.visemes(words, lang=lang), indent=1))
    print(f"{len(SENTENCES)} videos in {out}")


if __name__ == "__main__":
    main()
