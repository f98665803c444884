#!/usr/bin/env bash
# Each module may include only headers of the modules it depends on (CMakeLists.txt), so the data
# flow stays one-way. Lists the offending includes and fails if there are any.
set -u
SRC=$1
declare -A allowed=(
	[base]="base"
	[geometry]="base geometry"
	[image]="base geometry image"
	[warp]="base geometry image warp"
	[model]="base geometry image warp model"
	[media]="base geometry image media"
	[corpus]="base geometry image warp model media phonetics synth corpus"
	[phonetics]="base phonetics"
	[synth]="base geometry image warp model phonetics synth"
	[align]="base media image geometry phonetics align"
	[track]="base geometry image warp model media phonetics synth align corpus perform track"
	[perform]="base geometry image warp model media phonetics synth align perform"
	[render]="base geometry image warp model media phonetics synth corpus perform render"
	[stimuli]="base geometry image warp model media phonetics synth perform render stimuli"
	[serve]="base geometry image warp model media phonetics synth perform render serve"
	[viz]="base geometry image warp model viz"
	[cli]="base geometry image warp model media corpus viz phonetics synth align track perform render stimuli serve cli"
	[python]="base render cli python"
)
fail=0
for dir in "$SRC"/*/; do
	mod=$(basename "$dir")
	[ -n "${allowed[$mod]+x}" ] || { echo "module '$mod' is not in the dependency table of this test"; fail=1; continue; }
	while IFS= read -r line; do
		inc=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"${line#*:}")
		case " ${allowed[$mod]} " in *" $inc "*) ;; *) echo "forbidden: $line"; fail=1 ;; esac
	done < <(grep -rHn '#include "[a-z_]*/' "$dir")
done
# Outside src/: corpus-tools/ (a library under the CLI: image, phonetics and media, as CMakeLists.txt links
# it; its dlib check program reads corpora), and bench/ and examples/, which use the library as a program would: any module, never the CLI's
# own code (what a program needs is in the library), never a path into src/ ("../src/…").
check_dir() {  # DIR ALLOWED-MODULES
	local dir=$1 allowed=$2
	[ -d "$dir" ] || return 0
	while IFS= read -r line; do
		inc=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"${line#*:}")
		case " $allowed " in *" $inc "*) ;; *) echo "forbidden: $line"; fail=1 ;; esac
	done < <(grep -rHn --include='*.cpp' --include='*.h' '#include "[a-z_]*/' "$dir")
	if grep -rHn --include='*.cpp' --include='*.h' '#include "\.\./' "$dir"; then echo "forbidden: relative includes above"; fail=1; fi
}
root=$(dirname "$SRC")
check_dir "$root/corpus-tools" "base geometry image media phonetics corpus"
library="base geometry image warp model media phonetics corpus synth align perform track render stimuli serve viz"
check_dir "$root/bench" "$library"
check_dir "$root/examples" "$library"
[ $fail = 0 ] && echo "module dependencies ok"
exit $fail
