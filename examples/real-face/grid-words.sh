# GRID file-name letters → the sentence (../shared/data/README.md); sourced by examples/real-face/run.sh
# and bench/drive.sh.
grid_words() { # GRID file-name letters → words (../shared/data/README.md)
	local name=$1 out=()
	case ${name:0:1} in b) out+=(bin) ;; l) out+=(lay) ;; p) out+=(place) ;; s) out+=(set) ;; esac
	case ${name:1:1} in b) out+=(blue) ;; g) out+=(green) ;; r) out+=(red) ;; w) out+=(white) ;; esac
	case ${name:2:1} in a) out+=(at) ;; b) out+=(by) ;; i) out+=(in) ;; w) out+=(with) ;; esac
	# the letter (GRID's speakers are British: "z" is "zed")
	if [ "${name:3:1}" = z ]; then out+=(zed); else out+=("${name:3:1}"); fi
	case ${name:4:1} in z) out+=(zero) ;; 1) out+=(one) ;; 2) out+=(two) ;; 3) out+=(three) ;; 4) out+=(four) ;; 5) out+=(five) ;;
		6) out+=(six) ;; 7) out+=(seven) ;; 8) out+=(eight) ;; 9) out+=(nine) ;; esac
	case ${name:5:1} in a) out+=(again) ;; n) out+=(now) ;; p) out+=(please) ;; s) out+=(soon) ;; esac
	echo "${out[*]}"
}
