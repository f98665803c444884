#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a pt-BR phone transcript (TSV, seconds) of about DURATION seconds: "Que notícia excelente!"
repeated with pauses. usage: bench/make_utterance.py DURATION OUT.tsv"""
import sys
phones = [("k", .08), ("i", .07), ("n", .06), ("o", .09), ("t", .07), ("i", .08), ("s", .09), ("e", .08), ("l", .07), ("ẽ", .14),
          ("t", .07), ("ɪ", .08), ("", .22)]
target, out = float(sys.argv[1]), sys.argv[2]
t, rows = 0.0, []
while t < target:
    for p, d in phones:
        rows.append("%.3f\t%.3f\t%s" % (t, t + d, p))
        t += d
open(out, "w").write("\n".join(rows) + "\n")
