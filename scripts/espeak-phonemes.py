#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Lists the phoneme names libespeak-ng reports for a voice, exactly as talkhead receives them
# (src/phonetics/espeak.cpp: espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_PHONEME_IPA, the event's
# 8-byte name). These can differ from `espeak-ng -x --ipa` (ties, length marks, 8-byte cut).
#   scripts/espeak-phonemes.py VOICE [FILE]    text from FILE (default stdin), one sentence a line
# Prints "count<TAB>name<TAB>example word" per name, most frequent first. Use it when adding a language
# (phonetics/README.md): every name it prints must have a row in phonetics/<tag>/symbols.tsv.
import collections
import ctypes
import sys


class Event(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("unique_identifier", ctypes.c_uint), ("text_position", ctypes.c_int),
                ("length", ctypes.c_int), ("audio_position", ctypes.c_int), ("sample", ctypes.c_int),
                ("user_data", ctypes.c_void_p), ("id", ctypes.c_char * 8)]


PHONEME, WORD = 7, 1
PAUSES = {"", "_", "_:", "_!", "||", "|"}


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__ if __doc__ else "usage: espeak-phonemes.py VOICE [FILE]")
    voice = sys.argv[1]
    text = open(sys.argv[2], encoding="utf-8").read() if len(sys.argv) > 2 else sys.stdin.read()
    lib = ctypes.CDLL("libespeak-ng.so.1")
    if lib.espeak_Initialize(2, 0, None, 0x3) <= 0:
        sys.exit("cannot initialise espeak-ng")
    names = []
    CB = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int, ctypes.POINTER(Event))

    def cb(wav, n, ev):
        i = 0
        while ev[i].type != 0:
            if ev[i].type == PHONEME:
                names.append(bytes(ev[i].id).split(b"\0")[0].decode("utf-8", "replace"))
            i += 1
        return 0

    callback = CB(cb)
    lib.espeak_SetSynthCallback(callback)
    if lib.espeak_SetVoiceByName(voice.encode()) != 0:
        sys.exit("espeak-ng has no voice '%s'" % voice)
    counts, example = collections.Counter(), {}
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        for word in line.split():
            names.clear()
            z = word.encode("utf-8") + b"\0"
            lib.espeak_Synth(z, len(z), 0, 1, 0, 1, None, None)
            lib.espeak_Synchronize()
            for n in names:
                if n not in PAUSES:
                    counts[n] += 1
                    example.setdefault(n, word)
        names.clear()
        z = line.encode("utf-8") + b"\0"  # the whole sentence too: liaison, sandhi
        lib.espeak_Synth(z, len(z), 0, 1, 0, 1, None, None)
        lib.espeak_Synchronize()
        for n in names:
            if n not in PAUSES:
                counts[n] += 1
                example.setdefault(n, line[:40])
    for n, c in counts.most_common():
        print("%d\t%s\t%s" % (c, n, example[n]))


if __name__ == "__main__":
    main()
