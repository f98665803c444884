// SPDX-License-Identifier: GPL-3.0-or-later
// talkhead corpus synth -o DIR; talkhead corpus au-templates CORPUS -o F.tsv
#include <chrono>
#include <filesystem>
#include <cstdio>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "base/progress.h"
#include "corpus/build.h"
#include "corpus/corpus.h"
#include "phonetics/labels.h"
#include "media/image_io.h"
#include "synth/action_units.h"
#include "synth/au_appearance.h"
#include "synth/coarticulation.h"
#include "track/coarticulation_data.h"
#include "cli/video_options.h"
#include "synth_corpus.h"

namespace talkhead::cli {

namespace {

int runSynth(const std::vector<std::string>& argv) {
	Args args("corpus synth", "talkhead corpus synth -o DIR [options]",
	          {{"--output", "DIR", "folder to write the PNG images and corpus.csv into (required)", "-o"},
	           {"--size", "WxH", "image size (default 1280x720; the thesis used 1920x1080)"},
	           {"--seed", "N", "seed of the per-image head jitter (default 1)"},
	           {"--emotions", "LIST", "comma-separated emotion labels or aliases (default: all 23)"},
	           {"--visemes", "LIST", "comma-separated viseme labels or ASCII aliases (default: all 34)"},
	           {"--threads", "N", "worker threads (default: all cores)"},
	           {"--quiet", "", "no progress bar and no summary", "-q"}},
	          "Writes the synthetic expressive viseme corpus in CH-Unicamp CSV format: one image of a parametric,\n"
	          "shaded 2D face per (expression x viseme) — 23 x 34 = 782 at full settings — with its 56\n"
	          "ch-unicamp-56 feature points as exact ground truth. Build a model from it with\n"
	          "'talkhead build DIR/corpus.csv -o face.thm'.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("corpus synth: unexpected argument '" + args.positionals()[0] + "'");
	const std::string out = args.required("--output", "-o DIR is required");
	SynthCorpusOptions o;
	if (auto s = args.get("--size")) parseSize("corpus synth: --size", *s, o.width, o.height, 64, false);
	o.seed = std::uint64_t(args.number("--seed", 1, 0, 9.0e15));
	o.threads = unsigned(args.number("--threads", 0, 0, 256));
	if (auto e = args.get("--emotions"))
		for (const auto& name : split(*e, ',')) {
			auto c = canonicalEmotion(name);
			if (!c) {
				std::string known;
				for (const auto& l : emotionLabels()) known += (known.empty() ? "" : ", ") + l.label;
				throw UsageError("corpus synth: unknown emotion '" + name + "' (known: " + known + ")");
			}
			o.emotions.push_back(*c);
		}
	if (auto v = args.get("--visemes"))
		for (const auto& name : split(*v, ',')) {
			auto c = canonicalViseme(name);
			if (!c) {
				std::string known;
				for (const auto& l : visemeLabels()) known += (known.empty() ? "" : " ") + l.label;
				throw UsageError("corpus synth: unknown viseme '" + name + "' (known: " + known + ")");
			}
			o.visemes.push_back(*c);
		}
	const bool quiet = args.has("--quiet");
	const auto t0 = std::chrono::steady_clock::now();
	ProgressBar bar(quiet);
	writeSynthCorpus(out, o, bar);
	bar.finish();
	if (!quiet) {
		const std::size_t n = (o.emotions.empty() ? emotionLabels().size() : o.emotions.size()) *
		                      (o.visemes.empty() ? visemeLabels().size() : o.visemes.size());
		double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		std::fprintf(stderr, "wrote %s/corpus.csv: %zu images %dx%d in %.1f s\n", out.c_str(), n, o.width, o.height, secs);
	}
	return 0;
}

int runAuTemplates(const std::vector<std::string>& argv) {
	Args args("corpus au-templates", "talkhead corpus au-templates CORPUS -o TEMPLATES.tsv [options]",
	          {{"--output", "F.tsv", "template file to write (required; the shipped ones are models/au-templates/SCHEME.tsv)", "-o"},
	           {"--scheme", "NAME|FILE", "landmark scheme (default: from the corpus)"},
	           {"--profiles", "F.tsv", "each emotion's action units (default: corpus-tools/data/expression-aus.tsv)"},
	           {"--quiet", "", "no summary", "-q"}},
	          "Learns action-unit shape templates (D48) from a corpus that has the emotions: every (emotion, CDV)\n"
	          "shape is aligned to the neutral shape of the same CDV and its displacement, in units of the\n"
	          "inter-ocular distance, fitted by ridge least squares as the sum of its emotion's action units\n"
	          "(--profiles) times one template each. 'render --controls' (\"au\" events) and\n"
	          "'--emotion-source au' use the templates of the model's scheme.");
	if (!args.parse(argv)) return 0;
	args.onePositional("expected one CORPUS (a CSV or a folder)");
	const std::string out = args.required("--output", "-o F.tsv is required");
	const std::string path = args.positionals()[0];
	const Corpus corpus = loadCorpus(path);
	const Scheme scheme = loadScheme(args.get("--scheme", corpus.schemeName));
	const auto profiles = args.get("--profiles") ? loadAuProfiles(*args.get("--profiles")) : defaultAuProfiles();
	std::vector<LabelledShape> shapes;
	for (const auto& e : corpus.entries) shapes.push_back({e.emotionLabel(), e.cdvLabel(), e.points});
	const AuFit fit = learnAuTemplates(scheme, shapes, profiles);
	char summary[256];
	std::snprintf(summary, sizeof summary, "%zu (emotion, CDV) shapes; displacement rms %.4f, residual rms %.4f (inter-ocular distances)", fit.pairs,
	              fit.rmsData, fit.rmsResidual);
	std::string comment = "Action-unit shape templates for scheme " + scheme.name + " (decision D48): per AU and point, the displacement from the\n"
	                      "neutral face at full intensity in inter-ocular distances, x toward the image-right eye, y down the face.\n"
	                      "Learned by 'talkhead corpus au-templates' from " + std::filesystem::path(path).filename().string() + ": " + summary + ".";
	if (!fit.unused.empty()) {
		comment += "\nNo profile uses";
		for (const auto& au : fit.unused) comment += " " + au;
		comment += ": no template.";
	}
	writeFileAtomically(out, formatAuTemplates(fit.templates, scheme, comment));
	if (!args.has("--quiet"))
		std::fprintf(stderr, "wrote %s: %zu action units x %d points from %s\n", out.c_str(), fit.templates.names.size(), scheme.pointCount(), summary);
	return 0;
}

int runAuAppearance(const std::vector<std::string>& argv) {
	Args args("corpus au-appearance", "talkhead corpus au-appearance CORPUS -o F.bin [options]",
	          {{"--output", "F.bin", "the appearance maps to write (required; the installed ones are models/au-appearance.bin)", "-o"},
	           {"--scheme", "NAME|FILE", "landmark scheme (default: from the corpus)"},
	           {"--profiles", "F.tsv", "each emotion's action units (default: corpus-tools/data/expression-aus.tsv)"},
	           {"--grid", "W", "width of the maps' grid in pixels (default 256)"},
	           {"--quiet", "", "no summary", "-q"}},
	          "Learns what each action unit does to the skin (issue 31, decision D61): every (emotion, CDV) image and\n"
	          "its CDV's neutral image are warped to the neutral rest shape, and the log of their luminance ratio\n"
	          "is fitted per pixel, by ridge least squares, as the sum of the emotion's action units (--profiles)\n"
	          "times one map each (expression ratio images, Liu, Shan & Zhang 2001). Rendering with action units\n"
	          "('--emotion-source au', or auto for an emotion the model lacks) changes the skin by them.");
	if (!args.parse(argv)) return 0;
	args.onePositional("expected one CORPUS (a CSV or a folder)");
	const std::string out = args.required("--output", "-o F.bin is required");
	const std::string path = args.positionals()[0];
	const auto t0 = std::chrono::steady_clock::now();
	const Corpus corpus = loadCorpus(path);
	const Scheme scheme = loadScheme(args.get("--scheme", corpus.schemeName));
	const auto profiles = args.get("--profiles") ? loadAuProfiles(*args.get("--profiles")) : defaultAuProfiles();
	const AuAppearance a = buildAuAppearance(corpus, scheme, profiles, int(args.number("--grid", 256, 32, 2048)));
	saveAuAppearance(a, out);
	if (!args.has("--quiet"))
		std::fprintf(stderr, "wrote %s: %zu action units on a %dx%d grid from %s in %.1f s\n", out.c_str(), a.names.size(), a.width, a.height, a.source.c_str(),
		             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
	return 0;
}

double pearson(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
	const Eigen::ArrayXd x = a.array() - a.mean(), y = b.array() - b.mean();
	const double d = std::sqrt((x * x).sum() * (y * y).sum());
	return d > 0 ? (x * y).sum() / d : 0.0;
}

int runCoarticulation(const std::vector<std::string>& argv) {
	Args args("corpus coarticulation", "talkhead corpus coarticulation --clips LIST.tsv -o F.tsv [options]",
	          {{"--clips", "LIST.tsv", "real speakers' clips: columns landmarks ('talkhead corpus landmarks' TSV) and transcript (timed phones or words), optional speaker (required)"},
	           {"--output", "F.tsv", "the model to write (required)", "-o"},
	           {"--lang", "LANG", languageOptionHelp("the transcripts'")},
	           {"--lambda", "L", "ridge penalty (default 10)"},
	           {"--visual-lead", "S", "move every keypose by S seconds (< 0: earlier) where talkhead's aligner timed the phones: its times come late against the mouth (corpus-tools/visual-lead.sh measures it; default none)"},
	           {"--fps", "N", "frame rate the keyposes are placed at (default 25)"},
	           {"--quiet", "", "no summary", "-q"}},
	          "Learns coarticulation (issue 32, decision D62): the inner-lip opening of real speakers at each phone's\n"
	          "keypose, in units of the speaker's own 90th percentile in speech, fitted by ridge least squares from\n"
	          "the phone and two phones each side (their CDVs' mouth targets, bilabial, labiodental, pause, duration;\n"
	          "CDV indicators for the phone and its neighbours). With a speaker column, also reports how well it\n"
	          "predicts each speaker's openings when learned from the others (leave one speaker out). Render with\n"
	          "'--coarticulation F.tsv'. It also learns the speakers' mean mouth before their first words, which\n"
	          "pauses 'still' hold there, their mean mouth at rest after their last words, which a pause's rest is\n"
	          "drawn no more open than, and how long before or after their keypose /p b m/ shut.");
	if (!args.parse(argv)) return 0;
	if (!args.positionals().empty()) throw UsageError("corpus coarticulation: unexpected argument '" + args.positionals()[0] + "'");
	const std::string list = args.required("--clips", "--clips LIST.tsv is required");
	const std::string out = args.required("--output", "-o F.tsv is required");
	const double lambda = args.number("--lambda", 10, 0, 1e6);
	const Ticks frame = FrameRate{int(args.number("--fps", 25, 1, 1000)), 1}.frameLength();
	const Language& lang = languageOption(args);
	const CoarticulationList clips = readCoarticulationList(list, lang);
	std::vector<Eigen::MatrixXd> xs(clips.clips.size()), ys(clips.clips.size());
	for (std::size_t i = 0; i < clips.clips.size(); ++i) coarticulationExamples(clips.clips[i], frame, xs[i], ys[i]);
	CoarticulationModel m = fitCoarticulation(xs, ys, lambda);
	learnLeadingPause(m, clips.clips);
	learnTrailingPause(m, clips.clips);
	learnBilabialLead(m, clips.clips, frame);
	if (args.has("--visual-lead")) m.visualLead = args.number("--visual-lead", 0, -kMaxVisualLead, kMaxVisualLead);
	m.source = std::to_string(clips.clips.size()) + " clips of " + std::filesystem::path(list).filename().string();
	// Leave one speaker out: each speaker's keyposes predicted by a model of the others.
	std::vector<std::string> speakers;
	for (const auto& sp : clips.speakers)
		if (!sp.empty() && std::find(speakers.begin(), speakers.end(), sp) == speakers.end()) speakers.push_back(sp);
	std::string held;
	if (speakers.size() > 1) {
		double sum = 0;
		for (const std::string& sp : speakers) {
			std::vector<Eigen::MatrixXd> tx, hx, ty, hy;
			for (std::size_t i = 0; i < xs.size(); ++i) (clips.speakers[i] == sp ? hx : tx).push_back(xs[i]), (clips.speakers[i] == sp ? hy : ty).push_back(ys[i]);
			const CoarticulationModel o = fitCoarticulation(tx, ty, lambda);
			Eigen::Index n = 0;
			for (const auto& y : hy) n += y.rows();
			Eigen::VectorXd truth(n), guess(n);
			n = 0;
			for (std::size_t i = 0; i < hx.size(); ++i) {
				truth.segment(n, hy[i].rows()) = hy[i].col(0);
				guess.segment(n, hy[i].rows()) = (hx[i] * o.weights).array() + o.intercept;
				n += hy[i].rows();
			}
			sum += pearson(truth, guess);
		}
		char b[120];
		std::snprintf(b, sizeof b, "; held-out speakers' keypose openings r %.3f (mean of %zu)", sum / double(speakers.size()), speakers.size());
		held = b;
	}
	Eigen::Index n = 0;
	for (const auto& y : ys) n += y.rows();
	Eigen::VectorXd truth(n), fit(n);
	n = 0;
	for (std::size_t i = 0; i < xs.size(); ++i)
		truth.segment(n, ys[i].rows()) = ys[i].col(0), fit.segment(n, ys[i].rows()) = (xs[i] * m.weights).array() + m.intercept, n += ys[i].rows();
	saveCoarticulation(m, out);
	if (m.leadOpening) {
		char b[120];
		std::snprintf(b, sizeof b, "; lips before the first words %.2f of the opening (%zu clips)", *m.leadOpening, m.leadClips);
		held += b;
	}
	if (m.bilabialLead) {
		char b[120];
		std::snprintf(b, sizeof b, "; /p b m/ shut %+.0f ms from their keypose (%zu closures)", 1000 * *m.bilabialLead, m.bilabialCount);
		held += b;
	}
	if (m.visualLead) {
		char b[120];
		std::snprintf(b, sizeof b, "; every keypose moved %+.0f ms (the visual lead)", 1000 * *m.visualLead);
		held += b;
	}
	if (!args.has("--quiet"))
		std::fprintf(stderr, "wrote %s: %zu features from %zu keyposes of %zu clips; fit r %.3f%s\n", out.c_str(), m.features.size(), m.samples,
		             clips.clips.size(), pearson(truth, fit), held.c_str());
	return 0;
}

}  // namespace

int runCorpus(const std::vector<std::string>& argv) {
	if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
		std::printf("usage: talkhead corpus synth -o DIR [options]                        the synthetic corpus\n"
		            "       talkhead corpus landmarks VIDEO|FOLDER -o DIR [options]         68 face points per frame (dlib)\n"
		            "       talkhead corpus from-video VIDEO [--text T] -o DIR [options]    a viseme corpus from a video\n"
		            "       talkhead corpus au-templates CORPUS -o F.tsv [options]          action-unit shape templates\n"
		            "       talkhead corpus au-appearance CORPUS -o F.bin [options]         action-unit appearance maps\n"
		            "       talkhead corpus coarticulation --clips LIST.tsv -o F.tsv        coarticulation from real speakers\n"
		            "(see 'talkhead corpus SUBCOMMAND --help')\n");
		return argv.empty() ? 2 : 0;
	}
	if (argv[0] == "synth") return runSynth(std::vector<std::string>(argv.begin() + 1, argv.end()));
	const std::vector<std::string> rest(argv.begin() + 1, argv.end());
	if (argv[0] == "landmarks") return runCorpusLandmarks(rest);
	if (argv[0] == "from-video") return runCorpusFromVideo(rest);
	if (argv[0] == "au-templates") return runAuTemplates(rest);
	if (argv[0] == "au-appearance") return runAuAppearance(rest);
	if (argv[0] == "coarticulation") return runCoarticulation(rest);
	throw UsageError("corpus: unknown subcommand '" + argv[0] + "' (expected synth, landmarks, from-video, au-templates, au-appearance or coarticulation)");
}

}  // namespace talkhead::cli
