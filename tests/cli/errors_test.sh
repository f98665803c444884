#!/usr/bin/env bash
# Bad input: one clear error line naming the file, the right exit code, no partial output.
set -u
TH=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0
check() {  # check NAME EXPECTED_RC PATTERN -- command...
	local name=$1 rc=$2 pattern=$3; shift 4
	"$@" >"$T/out" 2>"$T/err"; local got=$?
	local lines; lines=$(wc -l <"$T/err")
	if [ "$got" != "$rc" ] || ! grep -q -- "$pattern" "$T/err" || [ "$lines" != 1 ]; then
		echo "FAIL $name: rc=$got (want $rc), stderr ($lines lines):"; cat "$T/err"; fail=1
	else
		echo "ok   $name: $(cat "$T/err")"
	fi
}
"$TH" >/dev/null 2>"$T/err"; [ $? = 2 ] && grep -q "^usage: talkhead" "$T/err" || { echo "FAIL no args"; fail=1; }
check "unknown command" 2 "unknown command 'frobnicate'" -- "$TH" frobnicate
check "unknown option" 2 "unknown option '--bogus'" -- "$TH" build --bogus
check "missing -o" 2 "-o MODEL.thm is required" -- "$TH" build "$T"
check "missing corpus" 1 "$T/nope: corpus not found" -- "$TH" build "$T/nope" -o "$T/m.thm"
check "bad --evr" 2 "--evr values must be in" -- "$TH" build "$T" -o "$T/m.thm" --evr 1.5
check "empty folder" 1 "no .asf or .pts shape files" -- "$TH" build "$T" -o "$T/m.thm"
printf 'a.png,joy,k,i,n,o,t,<t1>,word,(1;2)\n' >"$T/short.csv"
check "malformed csv" 1 "$T/short.csv:1: expected image, emotion, 5 phones, CDV, word and 56, 68 or 73 points, found 10 columns" -- "$TH" build "$T/short.csv" -o "$T/m.thm"
check "missing model" 1 "$T/none.thm: cannot open model" -- "$TH" inspect "$T/none.thm"
printf 'TALKHEAD garbage' >"$T/bad.thm"
check "corrupt model" 1 "$T/bad.thm" -- "$TH" inspect "$T/bad.thm"
head -c 100000 /dev/urandom >"$T/random.thm"
check "random bytes model" 1 "not a talkhead model file" -- "$TH" inspect "$T/random.thm"
[ -e "$T/m.thm" ] && { echo "FAIL: a model file was left behind"; fail=1; }
"$TH" --version | grep -q '^talkhead [0-9]' || { echo "FAIL --version"; fail=1; }
"$TH" build --help | grep -q -- '--components' || { echo "FAIL build --help"; fail=1; }
"$TH" inspect --help | grep -q -- '--recon' || { echo "FAIL inspect --help"; fail=1; }
exit $fail
