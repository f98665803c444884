#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Writes phonetics/generic/inventory.tsv and symbols.tsv: the table `--generic-visemes` maps IPA through for a
# language without a table of its own. Built from the language tables (phonetics/<tag>/), so that a phone
# maps as the tables map it; where they disagree, DECISIONS below say which reading is generic (the IPA
# symbol's own articulation, not one language's allophone). Re-run after adding or changing a language:
#   scripts/make-generic-phonetics.py            (from the repository root)
import os
import unicodedata

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "phonetics")
LANGS = ["pt-BR", "en-US", "es", "fr", "de", "it"]

# phone: (kind, group, vclass, cdv, note) - where the tables disagree, or phones no table has.
DECISIONS = {
    "ə": ("vowel", "-", "a", "ɐ", "Decision: schwa unrounded (pt-BR en-US de) -> <ɐ>; French rounded e muet is fr-only (<o>)."),
    "ɫ": ("liquid", "l", "-", "-", "Decision: velarised lateral -> group l (en-US); pt-BR's vocalised coda l [w] is pt-BR-only."),
    "ʁ": ("liquid", "ʁ", "-", "-", "Decision: uvular r -> rhotic group ʁ, liquid (it closes clusters in fr de; pt-BR's strong r never clusters)."),
    "x": ("consonant", "k", "-", "-", "Decision: velar fricative -> group k (en-US es fr de); pt-BR's strong-r reading is pt-BR-only."),
    "h": ("consonant", "k", "-", "-", "Decision: glottal fricative -> group k: the next vowel picks k1/k2/k3 (en-US es fr de)."),
    "ɦ": ("consonant", "k", "-", "-", "Decision: voiced glottal fricative -> group k, as h (en-US)."),
    "ɣ": ("consonant", "k", "-", "-", "Decision: velar fricative/approximant -> group k (es); pt-BR's strong-r reading is pt-BR-only."),
    "χ": ("consonant", "ʁ", "-", "-", "Uvular fricative -> rhotic group ʁ with ʁ (pt-BR)."),
    "ɹ": ("liquid", "ʁ", "-", "-", "Decision: alveolar approximant r -> rhotic group ʁ, liquid; en-US's rounded <r2> is English-only."),
    "ɻ": ("liquid", "ʁ", "-", "-", "Retroflex approximant r -> rhotic group ʁ, liquid."),
    "ɾ": ("liquid", "ʁ", "-", "-", "Decision: tap -> rhotic group ʁ, liquid (pt-BR es de it); en-US's flap-as-t is English-only."),
    "r": ("liquid", "ʁ", "-", "-", "Decision: trill -> rhotic group ʁ, liquid (de it: it closes clusters)."),
    "ʀ": ("liquid", "ʁ", "-", "-", "Uvular trill -> rhotic group ʁ, liquid."),
    "ʔ": ("consonant", "k", "-", "-", "Decision: glottal stop -> group k as h (de): no oral gesture; en-US's t allophone is English-only."),
    # Phones no table has (other espeak-ng languages, IPA transcripts).
    "ã": ("vowel", "-", "a", "a", "Nasal a -> <a>, as pt-BR ɐ̃ and fr ɑ̃."),
    "ɯ": ("vowel", "-", "i", "ɪ", "Close back unrounded (tr ı, ja u) -> <ɪ>: spread lips, close jaw; i-class."),
    "ɵ": ("vowel", "-", "u", "o", "Close-mid central rounded (sv, nl, ru) -> <o>; u-class."),
    "ɤ": ("vowel", "-", "a", "ɐ", "Close-mid back unrounded (bg, et) -> <ɐ>: unrounded mid."),
    "ɘ": ("vowel", "-", "a", "ɐ", "Close-mid central unrounded -> <ɐ>."),
    "ɜ": ("vowel", "-", "a", "ɐ", "Open-mid central unrounded -> <ɐ> (en-US reads it as r-coloured ɝ; de as vocalised r ɐ)."),
    "ɞ": ("vowel", "-", "u", "ɔ", "Open-mid central rounded -> <ɔ>; u-class."),
    "ɶ": ("vowel", "-", "u", "ɔ", "Open front rounded -> <ɔ>; u-class."),
    "ʍ": ("glide", "-", "u", "ʊ", "Voiceless labial-velar -> <ʊ> as w; u-class."),
    "ɰ": ("glide", "-", "i", "ɪ", "Velar approximant (tr ğ, ko) -> <ɪ>: unrounded glide; i-class."),
    "ʋ": ("consonant", "f", "-", "-", "Labiodental approximant (nl w, hi) -> group f: lower lip to upper teeth."),
    "ɸ": ("consonant", "p", "-", "-", "Bilabial fricative (ja fu) -> group p, as es β."),
    "ʙ": ("consonant", "p", "-", "-", "Bilabial trill -> group p."),
    "ɱ": ("consonant", "p", "-", "-", "Labiodental nasal -> group p (the tables spell it m)."),
    "ʈ": ("consonant", "t", "-", "-", "Retroflex stop (hi, sv) -> group t."),
    "ɖ": ("consonant", "t", "-", "-", "Retroflex stop -> group t."),
    "ɳ": ("consonant", "t", "-", "-", "Retroflex nasal -> group t."),
    "ɽ": ("liquid", "ʁ", "-", "-", "Retroflex flap -> rhotic group ʁ, liquid."),
    "ɭ": ("liquid", "l", "-", "-", "Retroflex lateral (espeak-ng ru, sv) -> group l."),
    "ɬ": ("liquid", "l", "-", "-", "Lateral fricative (cy ll) -> group l."),
    "ɮ": ("liquid", "l", "-", "-", "Voiced lateral fricative -> group l."),
    "ʟ": ("liquid", "l", "-", "-", "Velar lateral -> group l."),
    "ɕ": ("consonant", "ʃ", "-", "-", "Alveolo-palatal fricative (pl ś, zh x, sv) -> group ʃ."),
    "ʑ": ("consonant", "ʃ", "-", "-", "Alveolo-palatal fricative (pl ź) -> group ʃ."),
    "tɕ": ("consonant", "ʃ", "-", "-", "Alveolo-palatal affricate (pl ć, zh j) -> group ʃ, as tʃ."),
    "dʑ": ("consonant", "ʃ", "-", "-", "Alveolo-palatal affricate (pl dź) -> group ʃ."),
    "ʂ": ("consonant", "ʃ", "-", "-", "Retroflex fricative (pl sz, zh sh, ru ш) -> group ʃ."),
    "ʐ": ("consonant", "ʃ", "-", "-", "Retroflex fricative (pl ż) -> group ʃ."),
    "tʂ": ("consonant", "ʃ", "-", "-", "Retroflex affricate (pl cz, zh zh) -> group ʃ."),
    "dʐ": ("consonant", "ʃ", "-", "-", "Retroflex affricate (pl dż) -> group ʃ."),
    "ɧ": ("consonant", "ʃ", "-", "-", "Swedish sj-sound (espeak-ng sx) -> group ʃ: rounded, protruded."),
    "c": ("consonant", "k", "-", "-", "Palatal stop (cs ť, tr k) -> group k."),
    "ɟ": ("consonant", "k", "-", "-", "Palatal stop (cs ď, tr g) -> group k."),
    "q": ("consonant", "k", "-", "-", "Uvular stop (ar) -> group k."),
    "ɢ": ("consonant", "k", "-", "-", "Uvular stop -> group k."),
    "ɴ": ("consonant", "k", "-", "-", "Uvular nasal (ja) -> group k."),
    "ħ": ("consonant", "k", "-", "-", "Pharyngeal fricative (ar) -> group k, as h."),
    "ʕ": ("consonant", "k", "-", "-", "Pharyngeal fricative (ar) -> group k, as h."),
    "ʜ": ("consonant", "k", "-", "-", "Epiglottal fricative -> group k, as h."),
}

# Labels that mean one thing in one table and another elsewhere: not carried into the generic symbols.
SKIP_SYMBOLS = {"r", "ɜ", "ɜ˞", "æ", "y"}


def rows(path, n):
    out = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            out.append(line.split("\t"))
    assert all(len(r) == n for r in out), path
    return out[1:]


def main():
    inv, where = {}, {}
    for t in LANGS:
        for r in rows(os.path.join(ROOT, t, "inventory.tsv"), 6):
            where.setdefault(r[0], []).append(t)
            inv.setdefault(r[0], {})[t] = tuple(r[1:5])
    out_inv = []
    for p, by in inv.items():
        if p in DECISIONS:
            out_inv.append((p,) + DECISIONS[p])
            continue
        vals = set(by.values())
        if len(vals) != 1:
            raise SystemExit("tables disagree on %s: %s - add a DECISIONS row" % (p, by))
        kind, group, vclass, cdv = vals.pop()
        note = "As in " + " ".join(by) + "." if p != "_" else "Pause/silence -> <sil>."
        out_inv.append((p, kind, group, vclass, cdv, note))
    for p, d in DECISIONS.items():
        if p not in inv:
            out_inv.append((p,) + d)
    pause = [r for r in out_inv if r[0] == "_"]
    out_inv = [r for r in out_inv if r[0] != "_"] + pause
    phones = {r[0]: r for r in out_inv}

    sym = {}  # symbol -> (phones, notation, note); first wins
    order = []

    def add(s, ph, notation, note):
        s = unicodedata.normalize("NFC", s) if notation != "ipa-nfd" else s
        if s in sym or s in SKIP_SYMBOLS and notation != "canonical":
            return
        if any(x not in phones for x in ph.split()):
            return
        sym[s] = (ph, "ipa" if notation in ("canonical", "ipa-nfd") else notation, note)
        order.append(s)

    for p in phones:
        if p != "_":
            add(p, p, "canonical", "Canonical IPA phone.")
    for t in LANGS:
        for s, ph, notation, note in rows(os.path.join(ROOT, t, "symbols.tsv"), 4):
            if notation in ("ipa", "praat", "pause"):
                add(s, ph, notation, "From %s: %s" % (t, note))
    vowels = [p for p, r in phones.items() if r[1] == "vowel" and len(p) == 1 and r[4] not in ("r2",)]
    offglides = {"ɪ": "j", "i": "j", "j": "j", "ʊ": "w", "u": "w", "w": "w", "ə": "ə", "ɐ": "ɐ", "ʏ": "ʏ", "y": "ʏ"}
    for v in vowels:
        for g, ph in offglides.items():
            if g != v and (g not in "ʏy" or phones[v][3] == "u"):
                add(v + g, v + " " + ph, "ipa", "Generated: diphthong, vowel + offglide.")
        for g in ("j", "w"):
            add(g + v, g + " " + v, "ipa", "Generated: rising diphthong (espeak-ng ru ja ju, pl), glide + vowel.")
        nasal = unicodedata.normalize("NFC", v + "\u0303")
        add(nasal, nasal if nasal in phones else v, "ipa", "Generated: nasal vowel -> its oral keypose.")
    consonants = [p for p, r in phones.items() if r[1] in ("consonant", "liquid")]
    marks = [("ʲ", "palatalised", None), ("ʷ", "labialised", None), ("ʰ", "aspirated", None), ("ˠ", "velarised", "lnstdrɫ"),
             ("ˤ", "pharyngealised", "tdszlð"), ("\u032a", "dental", "tdnszlr"), ("\u0329", "syllabic", "lmnrɹɾʁ"),
             ("\u030d", "syllabic", "ŋ"), ("\u0325", "voiceless", "lmnrɹɾʁ"), ("\u031d", "raised", "rɾ")]
    for c in consonants:
        for mark, what, only in marks:
            if only is None or c in only:
                add(c + mark, c, "ipa", "Generated: %s %s -> %s." % (what, c, c))
    for s, ph, note in (("ʲ", "j", "espeak-ng's separate palatalisation event (pl, ru) -> j."), ("sx", "ɧ", "espeak-ng sv name of the sj-sound."),
                        ("r̝̊", "r", "Czech ř (voiceless) -> r."), ("r̝", "r", "Czech ř -> r."), ("ɡ", "g", "IPA script g -> g.")):
        add(s, ph, "ipa" if s != "sx" else "espeak", "Generated: " + note)

    with open(os.path.join(ROOT, "generic", "inventory.tsv"), "w", encoding="utf-8") as f:
        f.write(INV_HEAD)
        f.write("phone\tkind\tgroup\tvclass\tcdv\tnote\n")
        for r in out_inv:
            f.write("\t".join(r) + "\n")
    with open(os.path.join(ROOT, "generic", "symbols.tsv"), "w", encoding="utf-8") as f:
        f.write(SYM_HEAD)
        f.write("symbol\tphones\tnotation\tnote\n")
        for s in order:
            ph, notation, note = sym[s]
            f.write("\t".join((s, ph, notation, note)) + "\n")


INV_HEAD = """# inventory.tsv (generic) - GENERATED by scripts/make-generic-phonetics.py; edit the language tables or the
# script's DECISIONS, not this file. The phones `--generic-visemes` maps IPA through for a language without a
# table (docs/decisions.md D38): the union of the language tables' phones (../pt-BR ../en-US ../es ../fr ../de
# ../it), each mapped as the tables map it; where they disagree, the reading of the IPA symbol's own
# articulation wins over one language's allophone (the Decision rows); plus IPA phones no table has (retroflex,
# alveolo-palatal, uvular, pharyngeal consonants, more vowels) for other espeak-ng languages.
# Format and columns: as ../pt-BR/inventory.tsv.
"""
SYM_HEAD = """# symbols.tsv (generic) - GENERATED by scripts/make-generic-phonetics.py; do not edit. Every IPA spelling the
# language tables accept (their ipa, praat and pause rows; not their language-specific espeak/X-SAMPA/ARPAbet
# rows, nor r y æ ɜ whose reading differs between tables), each phone of inventory.tsv as itself, and
# generated IPA spellings: diphthongs (vowel + offglide, glide + vowel), nasal vowels (vowel + U+0303),
# consonants with a secondary articulation or diacritic (ʲ ʷ ʰ ˠ ˤ, dental, syllabic, voiceless, raised).
# A label still unknown goes by --unknown (talkhead say: the nearest known prefix).
# Format and columns: as ../pt-BR/symbols.tsv.
"""

if __name__ == "__main__":
    main()
