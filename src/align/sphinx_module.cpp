// SPDX-License-Identifier: GPL-3.0-or-later
// The pocketsphinx plugin (libtalkhead-sphinx.so). See sphinx_module.h.
#include <pocketsphinx.h>
#include <sphinxbase/cmn.h>
#include <sphinxbase/feat.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "align/sphinx_module.h"
#include "base/plugin.h"

namespace talkhead {

namespace {

struct SphinxHandle {
	cmd_ln_t* config = nullptr;
	ps_decoder_t* decoder = nullptr;
	std::vector<mfcc_t> cmnStart;  // the cepstral mean a fresh decoder starts from
	~SphinxHandle() {
		if (decoder) ps_free(decoder);
		if (config) cmd_ln_free_r(config);
	}
};

std::string numberText(double v) {
	char b[32];
	std::snprintf(b, sizeof b, "%g", v);
	return b;
}

void* openSphinx(const SphinxConfig& c, std::string& error) {
	auto h = std::make_unique<SphinxHandle>();
	const bool ok = guarded(error, [&] {
		namespace fs = std::filesystem;
		const std::string hmm = c.modelDir + "/en-us", lm = c.modelDir + "/en-us-phone.lm.bin";
		if (!fs::exists(hmm + "/mdef") || !fs::exists(lm))
			throw std::runtime_error(c.modelDir + ": no pocketsphinx en-US acoustic model and phone language model (en-us/mdef, en-us-phone.lm.bin): install the Debian package pocketsphinx-en-us, or set TALKHEAD_SPHINX_MODEL");
		const std::string beam = numberText(c.beam), pbeam = numberText(c.phoneBeam), lw = numberText(c.languageWeight);
		// Each utterance decoded as if alone: -cmn batch (its cepstral mean is its own; live CMN carries it over
		// from the utterances before), -remove_silence no (pocketsphinx's own voice activity drops frames —
		// shifting every time after them — and keeps its state between utterances; talkhead's split the audio
		// already) and -remove_noise no (its noise estimate is carried from utterance to utterance too; without
		// it GRID's training clips give more bilabials and fewer false ones, D95). -logfn /dev/null: pocketsphinx
		// logs every step to stderr otherwise.
		h->config = cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", hmm.c_str(), "-allphone", lm.c_str(), "-backtrace", "yes", "-beam", beam.c_str(),
		                        "-pbeam", pbeam.c_str(), "-lw", lw.c_str(), "-cmn", "batch", "-remove_silence", "no", "-dither", "no", "-remove_noise", "no", "-logfn", "/dev/null", nullptr);
		if (!h->config) throw std::runtime_error("pocketsphinx: the decoder's settings were refused");
		h->decoder = ps_init(h->config);
		if (!h->decoder) throw std::runtime_error(c.modelDir + ": pocketsphinx could not load its model (a damaged pocketsphinx-en-us?)");
		feat_t* feat = ps_get_feat(h->decoder);
		h->cmnStart.assign(std::size_t(feat_cepsize(feat)), 0);
		cmn_live_get(feat->cmn_struct, h->cmnStart.data());
	});
	return ok ? h.release() : nullptr;
}

bool decodeSphinx(void* hp, const std::int16_t* samples, std::size_t count, std::vector<SphinxPhone>& phones, std::string& error) {
	return guarded(error, [&] {
		SphinxHandle& h = *static_cast<SphinxHandle*>(hp);
		phones.clear();
		// The cepstral mean as a fresh decoder has it: whatever came before, an utterance decodes the same.
		cmn_live_set(ps_get_feat(h.decoder)->cmn_struct, h.cmnStart.data());
		if (ps_start_stream(h.decoder) < 0 || ps_start_utt(h.decoder) < 0) throw std::runtime_error("pocketsphinx: could not start an utterance");
		// The whole utterance in one call (batch CMN needs it).
		if (count > 0 && ps_process_raw(h.decoder, samples, count, FALSE, TRUE) < 0) throw std::runtime_error("pocketsphinx: decoding failed");
		if (ps_end_utt(h.decoder) < 0) throw std::runtime_error("pocketsphinx: could not end the utterance");
		for (ps_seg_t* s = ps_seg_iter(h.decoder); s; s = ps_seg_next(s)) {
			int sf = 0, ef = 0;
			ps_seg_frames(s, &sf, &ef);
			SphinxPhone p;
			p.start = sf;
			p.end = ef + 1;
			p.phone = ps_seg_word(s) ? ps_seg_word(s) : "";
			phones.push_back(std::move(p));
		}
	});
}

void closeSphinx(void* hp) { delete static_cast<SphinxHandle*>(hp); }

const SphinxModule kModule{kSphinxModuleAbi, openSphinx, decodeSphinx, closeSphinx};

}  // namespace

}  // namespace talkhead

extern "C" const void* talkhead_sphinx_module() { return &talkhead::kModule; }
