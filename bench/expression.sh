#!/usr/bin/env bash
# Do the default face's emotions read? An independent facial-expression classifier (face-api's 7-class
# expression net on an SSD MobileNet face detector, TensorFlow.js/WebAssembly, installed from npm on first
# run into ~/.cache/talkhead-bench) judges every 2nd frame of a rendered sentence per emotion; the clip's
# judgement is the class with the highest mean probability. Prints the confusion table (mean probability
# per class) and how many of joy, distress, anger, fear and hate read as happy, sad, angry, fearful and
# disgusted, and whether neutral stays neutral (issue 13's goal: >= 4 of 5, neutral neutral).
# usage: bench/expression.sh [BUILD_DIR] [--all] [--model M.thm | --face NAME] [--lang L --text "…"] [--au-appearance on|off]
#                            [--coarticulation on|off|F.tsv]
#   --all   also the other 17 OCC emotions (their expected class is their basis's basic emotion)
#   --au-appearance off   an emotion from action units changes the shape alone (issue 31: before and after)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"; all=0; model=(); lang=pt-BR; extra=()
texts=("O professor explicou a lição para toda a turma de manhã." "Ela abriu a carta e leu tudo em silêncio.")
while [ $# -gt 0 ]; do
	case "$1" in
		--all) all=1 ;;
		--model) model=(--model "$2"); shift ;;
		--face) model=(--face "$2"); shift ;;
		--au-appearance) extra+=(--au-appearance "$2"); shift ;;
		--coarticulation) extra+=(--coarticulation "$2"); shift ;;
		--lang) lang="$2"; shift ;;
		--text) texts=("$2"); shift ;;
		*) build="$1" ;;
	esac
	shift
done
th="$build/talkhead"
[ -x "$th" ] || { echo "expression.sh: $th not built (run scripts/build)" >&2; exit 1; }
command -v node >/dev/null && command -v npm >/dev/null || { echo "expression.sh: needs node and npm (apt install nodejs npm)" >&2; exit 1; }
cache="${XDG_CACHE_HOME:-$HOME/.cache}/talkhead-bench/expression"
if ! cmp -s "$root/bench/expression/package.json" "$cache/package.json" || [ ! -d "$cache/node_modules/@vladmandic/face-api" ]; then
	echo "installing the classifier into $cache (npm)…" >&2
	mkdir -p "$cache" && cp "$root/bench/expression/package.json" "$cache/"
	(cd "$cache" && npm install --no-audit --no-fund --loglevel=error >&2)
fi
export NODE_PATH="$cache/node_modules"

# emotion  expected class (the basic emotion its profile follows; corpus-tools/data/expression-aus.tsv)
rows=(neutral:neutral joy:happy distress:sad anger:angry fear:fearful hate:disgusted)
[ $all = 1 ] && rows+=(happy-for:happy pity:sad gloating:happy resentment:angry hope:happy satisfaction:happy
	fears-confirmed:sad relief:happy disappointment:sad pride:happy shame:sad admiration:happy reproach:angry
	gratification:happy remorse:sad gratitude:happy love:happy)
classes=(neutral happy sad angry fearful disgusted surprised)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores; classifier: @vladmandic/face-api $(node -p "require('$cache/node_modules/@vladmandic/face-api/package.json').version"), every 2nd frame; ${#texts[@]} sentence(s), $lang"
printf '%-16s' emotion; for c in "${classes[@]}"; do printf ' %9s' "$c"; done; printf '  %-10s %-10s %s\n' judged expected faces
ok5=0; neutral_ok=0
for row in "${rows[@]}"; do
	e="${row%%:*}"; want="${row#*:}"
	for i in "${!texts[@]}"; do
		"$th" say "${texts[$i]}" --lang "$lang" --emotion "$e" "${model[@]}" "${extra[@]}" --format y4m -o - --no-audio -q |
			node "$root/bench/expression/classify.js" 2 >"$tmp/$e.$i.json"
	done
	line=$(cat "$tmp/$e".*.json | node -e '
		const ls = require("fs").readFileSync(0, "utf8").trim().split("\n").map(JSON.parse);
		const cs = ["neutral","happy","sad","angry","fearful","disgusted","surprised"];
		let faces = 0, judged = 0; const m = {};
		for (const c of cs) m[c] = 0;
		for (const l of ls) { faces += l.faces; judged += l.judged; for (const c of cs) m[c] += l.mean[c] * l.faces; }
		for (const c of cs) m[c] = faces ? m[c] / faces : 0;
		const best = cs.reduce((a, b) => (m[b] > m[a] ? b : a));
		console.log(cs.map((c) => m[c].toFixed(3)).join(" ") + " " + best + " " + faces + "/" + judged);')
	read -r -a v <<<"$line"
	printf '%-16s' "$e"; for k in 0 1 2 3 4 5 6; do printf ' %9s' "${v[$k]}"; done
	mark=$([ "${v[7]}" = "$want" ] && echo "ok" || echo "MISS")
	printf '  %-10s %-10s %s %s\n' "${v[7]}" "$want" "${v[8]}" "$mark"
	case "$e" in
		neutral) [ "${v[7]}" = neutral ] && neutral_ok=1 ;;
		joy|distress|anger|fear|hate) [ "${v[7]}" = "$want" ] && ok5=$((ok5 + 1)) ;;
	esac
done
echo "basic five read as intended: $ok5 of 5 (goal >= 4); neutral reads neutral: $([ $neutral_ok = 1 ] && echo yes || echo no)"
