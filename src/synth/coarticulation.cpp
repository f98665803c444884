// SPDX-License-Identifier: GPL-3.0-or-later
// Coarticulation (issue 32, D62): phone context → mouth opening at each keypose, and the face's exemplar
// nearest it.
#include "synth/coarticulation.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "base/data_dirs.h"
#include "base/error.h"
#include "base/atomic_file.h"
#include "base/text.h"
#include "base/tsv.h"
#include "geometry/eigen_products.h"
#include "phonetics/emotion.h"

namespace talkhead {

namespace {

std::string number(double v) {
	char b[40];
	std::snprintf(b, sizeof b, "%.9g", v);
	return b;
}

struct CdvTargets {
	std::vector<std::string> cdvs;                          // table order
	std::map<std::string, std::pair<double, double>> value;  // opening, width (eye distances)
};

const CdvTargets& cdvTargets() {
	static const CdvTargets t = [] {
		const auto path = findDataFile("phonetics/cdv-mouth-targets.tsv");
		if (!path) throw Error("phonetics/cdv-mouth-targets.tsv: not found in the data folders (set TALKHEAD_DATA_DIR)");
		const TsvTable table = readTsv(*path);
		const std::size_t c = table.column("cdv"), o = table.column("opening"), w = table.column("width");
		CdvTargets out;
		for (const auto& row : table.rows) {
			out.cdvs.push_back(row.fields[c]);
			out.value[row.fields[c]] = {table.number(row, o, -1, 1), table.number(row, w, -1, 1)};
		}
		return out;
	}();
	return t;
}

bool labiodental(const std::string& cdv) { return cdv == "f1" || cdv == "f2"; }
bool pause(const PhoneSegment& p) { return p.cdv.isSilence() || p.phone == "_"; }
// A pause's rest keypose: its silence, neither the lips held before the first words nor the in-breath (D107).
bool restKeypose(const Keypose& k) { return k.cdv.isSilence() && !k.hold && !k.breath; }

constexpr int kSide = 2;        // phone runs each side
constexpr int kPerRun = 6;      // features per run
constexpr int kOneHotSide = 1;  // CDV indicators for offsets −1 … +1
constexpr double kWidthWeight = 0.15;      // exemplar choice: a width's miss (in the face's spread of widths) against the opening's

// The runs of phones (first, last) a keypose list stands on, each phone keypose's run index.
struct Run {
	std::size_t first, last;
};

}  // namespace

const std::vector<std::string>& coarticulationFeatureNames() {
	static const std::vector<std::string> names = [] {
		std::vector<std::string> n;
		for (int off = -kSide; off <= kSide; ++off) {
			const std::string at = (off > 0 ? "+" : "") + std::to_string(off);
			for (const char* f : {"open", "width", "bilabial", "labiodental", "pause", "logdur"}) n.push_back(std::string(f) + at);
		}
		for (int off = -kOneHotSide; off <= kOneHotSide; ++off)
			for (const auto& c : cdvTargets().cdvs) n.push_back("cdv" + std::string(off > 0 ? "+" : "") + std::to_string(off) + "=" + c);
		return n;
	}();
	return names;
}

bool isPhoneKeypose(const std::vector<PhoneSegment>& phones, const Keypose& key) {
	return !key.breath && key.first < phones.size() && !pause(phones[key.first]);
}

Eigen::MatrixXd coarticulationFeatures(const std::vector<PhoneSegment>& phones, const std::vector<Keypose>& keys, std::vector<std::size_t>& rows) {
	rows.clear();
	for (std::size_t i = 0; i < keys.size(); ++i)
		if (isPhoneKeypose(phones, keys[i])) rows.push_back(i);
	const CdvTargets& t = cdvTargets();
	const Eigen::Index nf = Eigen::Index(coarticulationFeatureNames().size());
	Eigen::MatrixXd X = Eigen::MatrixXd::Zero(Eigen::Index(rows.size()), nf);
	for (std::size_t r = 0; r < rows.size(); ++r) {
		const Keypose& k = keys[rows[r]];
		// The runs around: the keypose's own (first … last), then whole phones each side.
		auto runAt = [&](int off) -> std::optional<Run> {
			if (off == 0) return Run{k.first, std::min(k.last, phones.size() - 1)};
			long at = off < 0 ? long(k.first) + off : long(std::min(k.last, phones.size() - 1)) + off;
			if (at < 0 || at >= long(phones.size())) return std::nullopt;
			return Run{std::size_t(at), std::size_t(at)};
		};
		Eigen::Index col = 0;
		for (int off = -kSide; off <= kSide; ++off, col += kPerRun) {
			const auto run = runAt(off);
			const PhoneSegment* p = run ? &phones[run->first] : nullptr;
			const bool isPause = !p || pause(*p);
			const std::string cdv = isPause ? Cdv().label() : p->cdv.label();
			const auto it = t.value.find(cdv);
			const auto v = it == t.value.end() ? std::pair<double, double>{0, 0} : it->second;
			const double seconds = run ? toSeconds(phones[run->last].end - phones[run->first].start) : 0.5;
			X(Eigen::Index(r), col + 0) = 10 * v.first;
			X(Eigen::Index(r), col + 1) = 10 * v.second;
			X(Eigen::Index(r), col + 2) = bilabial(cdv);
			X(Eigen::Index(r), col + 3) = labiodental(cdv);
			X(Eigen::Index(r), col + 4) = isPause;
			X(Eigen::Index(r), col + 5) = std::log(std::max(0.02, std::min(seconds, 2.0)));
		}
		for (int off = -kOneHotSide; off <= kOneHotSide; ++off, col += Eigen::Index(t.cdvs.size())) {
			const auto run = runAt(off);
			const std::string cdv = !run || pause(phones[run->first]) ? Cdv().label() : phones[run->first].cdv.label();
			const auto it = std::find(t.cdvs.begin(), t.cdvs.end(), cdv);
			if (it != t.cdvs.end()) X(Eigen::Index(r), col + (it - t.cdvs.begin())) = 1;
		}
	}
	return X;
}

namespace {

// A clip's frames with a face (seconds, opening, width) and its scales: the 90th percentile of its opening
// and the median width in speech (frames inside a phone).
struct ClipFrames {
	std::vector<double> t, v, w;
	double scale = 0, widthScale = 0;
};

ClipFrames clipFrames(const CoarticulationClip& c) {
	if (c.times.size() != c.openings.size() || c.times.size() != c.widths.size())
		throw std::logic_error("coarticulation: a clip's times, openings and widths differ in length");
	ClipFrames f;
	std::vector<double> speech, speechWidth;
	for (std::size_t i = 0; i < c.times.size(); ++i) {
		if (!std::isfinite(c.openings[i]) || !std::isfinite(c.widths[i])) continue;
		f.t.push_back(c.times[i]), f.v.push_back(c.openings[i]), f.w.push_back(c.widths[i]);
		for (const PhoneSegment& p : c.phones)
			if (!pause(p) && toSeconds(p.start) <= c.times[i] && c.times[i] < toSeconds(p.end)) {
				speech.push_back(c.openings[i]), speechWidth.push_back(c.widths[i]);
				break;
			}
	}
	if (speech.size() < 5) throw Error(c.name + ": fewer than 5 frames with a face inside its phones: nothing to learn from");
	std::sort(speech.begin(), speech.end());
	std::sort(speechWidth.begin(), speechWidth.end());
	f.scale = speech[std::size_t(0.9 * double(speech.size() - 1))], f.widthScale = speechWidth[speechWidth.size() / 2];
	if (!(f.scale > 0) || !(f.widthScale > 0)) throw Error(c.name + ": the lips never part in its speech: nothing to learn from");
	return f;
}

}  // namespace

void coarticulationExamples(const CoarticulationClip& c, Ticks frame, Eigen::MatrixXd& X, Eigen::MatrixXd& y) {
	const ClipFrames f = clipFrames(c);
	const std::vector<double>&t = f.t, &v = f.v, &w = f.w;
	const double scale = f.scale, widthScale = f.widthScale;
	const std::vector<Keypose> keys = keyposes(c.phones, frame);
	std::vector<std::size_t> rows;
	X = coarticulationFeatures(c.phones, keys, rows);
	y.resize(Eigen::Index(rows.size()), 2);
	auto interpolate = [&](const std::vector<double>& values, double at) {
		const auto hi = std::lower_bound(t.begin(), t.end(), at);
		if (hi == t.begin()) return values.front();
		if (hi == t.end()) return values.back();
		const std::size_t j = std::size_t(hi - t.begin());
		const double u = (at - t[j - 1]) / (t[j] - t[j - 1]);
		return values[j - 1] + u * (values[j] - values[j - 1]);
	};
	for (std::size_t r = 0; r < rows.size(); ++r) {
		const double at = toSeconds(keys[rows[r]].time);
		y(Eigen::Index(r), 0) = interpolate(v, at) / scale;
		y(Eigen::Index(r), 1) = interpolate(w, at) / widthScale;
	}
}

CoarticulationModel fitCoarticulation(const std::vector<Eigen::MatrixXd>& xs, const std::vector<Eigen::MatrixXd>& ys, double lambda) {
	const Eigen::Index nf = Eigen::Index(coarticulationFeatureNames().size());
	Eigen::Index total = 0;
	for (const auto& x : xs) total += x.rows();
	if (total < 10) throw Error("coarticulation: " + std::to_string(total) + " keyposes to learn from: too few (give more clips)");
	if (total < nf && lambda <= 0)
		throw Error("coarticulation: " + std::to_string(total) + " keyposes, fewer than the " + std::to_string(nf) + " features: a ridge penalty (lambda > 0) is needed");
	// Ridge least squares with an unpenalised intercept: centre, solve (XᵀX + λI) w = Xᵀy.
	Eigen::MatrixXd X(total, nf), y(total, 2);
	Eigen::Index at = 0;
	for (std::size_t i = 0; i < xs.size(); ++i) X.middleRows(at, xs[i].rows()) = xs[i], y.middleRows(at, ys[i].rows()) = ys[i], at += xs[i].rows();
	const Eigen::RowVectorXd mean = X.colwise().mean(), ymean = y.colwise().mean();
	const Eigen::MatrixXd Xc = X.rowwise() - mean;
	pinEigenBlocking();  // products that round the same on every machine (D74)
	Eigen::MatrixXd A = Xc.transpose() * Xc;
	A.diagonal().array() += lambda;
	const Eigen::MatrixXd w = A.ldlt().solve(Xc.transpose() * (y.rowwise() - ymean));
	CoarticulationModel m;
	m.features = coarticulationFeatureNames();
	m.weights = w.col(0), m.widthWeights = w.col(1);
	m.intercept = ymean(0) - mean.dot(m.weights);
	m.widthIntercept = ymean(1) - mean.dot(m.widthWeights);
	m.lambda = lambda;
	m.samples = std::size_t(total);
	return m;
}

namespace {

// A clip's mean opening and width over its frames in [from, until) seconds, in its units; nullopt when none.
std::optional<std::pair<double, double>> meanMouthBetween(const CoarticulationClip& c, double from, double until) {
	const ClipFrames f = clipFrames(c);
	double open = 0, width = 0;
	std::size_t n = 0;
	for (std::size_t i = 0; i < f.t.size(); ++i)
		if (f.t[i] >= from && f.t[i] < until) open += f.v[i], width += f.w[i], ++n;
	if (n == 0) return std::nullopt;
	return std::pair{open / double(n) / f.scale, width / double(n) / f.widthScale};
}

// The mean over the clips of what `mouth` finds in each (the clips where it finds nothing left out).
template <class Mouth>
void meanOverClips(const std::vector<CoarticulationClip>& clips, Mouth mouth, std::optional<double>& opening, std::optional<double>& width, std::size_t& count) {
	double open = 0, wide = 0;
	std::size_t n = 0;
	for (const CoarticulationClip& c : clips)
		if (const auto m = mouth(c)) open += m->first, wide += m->second, ++n;
	count = n;
	if (n > 0) opening = open / double(n), width = wide / double(n);
}

}  // namespace

std::optional<std::pair<double, double>> leadingPauseMouth(const CoarticulationClip& c) {
	const auto speech = std::find_if(c.phones.begin(), c.phones.end(), [](const PhoneSegment& p) { return !pause(p); });
	if (speech == c.phones.end()) return std::nullopt;
	return meanMouthBetween(c, -std::numeric_limits<double>::infinity(), toSeconds(speech->start - kStillLead));
}

void learnLeadingPause(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips) {
	meanOverClips(clips, leadingPauseMouth, m.leadOpening, m.leadWidth, m.leadClips);
}

std::optional<std::pair<double, double>> trailingPauseMouth(const CoarticulationClip& c) {
	const auto last = std::find_if(c.phones.rbegin(), c.phones.rend(), [](const PhoneSegment& p) { return !pause(p); });
	if (last == c.phones.rend()) return std::nullopt;
	return meanMouthBetween(c, toSeconds(last->end + kRestAfter), std::numeric_limits<double>::infinity());
}

void learnTrailingPause(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips) {
	meanOverClips(clips, trailingPauseMouth, m.restOpening, m.restWidth, m.restClips);
}

std::vector<double> bilabialClosureOffsets(const CoarticulationClip& c, Ticks frame) {
	const ClipFrames f = clipFrames(c);
	std::vector<double> out;
	for (const Keypose& k : keyposes(c.phones, frame)) {
		if (!bilabial(k.cdv.label()) || !isPhoneKeypose(c.phones, k) || k.last >= c.phones.size()) continue;
		const double from = toSeconds(c.phones[k.first].start) - 0.04, to = toSeconds(c.phones[k.last].end) + 0.04;
		double least = std::numeric_limits<double>::max(), at = 0;
		for (std::size_t i = 0; i < f.t.size(); ++i)
			if (f.t[i] >= from && f.t[i] <= to && f.v[i] < least) least = f.v[i], at = f.t[i];
		if (least == std::numeric_limits<double>::max()) continue;
		const double offset = at - toSeconds(k.time);
		if (std::abs(offset) <= 0.1) out.push_back(offset);
	}
	return out;
}

void learnBilabialLead(CoarticulationModel& m, const std::vector<CoarticulationClip>& clips, Ticks frame) {
	double sum = 0;
	std::size_t n = 0;
	for (const CoarticulationClip& c : clips)
		for (double o : bilabialClosureOffsets(c, frame)) sum += o, ++n;
	m.bilabialCount = n;
	if (n > 0) m.bilabialLead = sum / double(n);
}

void applyBilabialLead(const CoarticulationModel& m, const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys, Ticks frame) {
	if (!m.bilabialLead || keys.empty()) return;
	const Ticks lead = ticksFromSeconds(*m.bilabialLead);
	for (std::size_t i = 0; i < keys.size(); ++i) {
		Keypose& k = keys[i];
		if (!bilabial(k.cdv.label()) || !isPhoneKeypose(phones, k)) continue;
		Ticks t = k.time + lead;
		if (i > 0) t = std::max(t, keys[i - 1].time + frame);
		if (i + 1 < keys.size()) t = std::min(t, keys[i + 1].time - frame);
		if ((i == 0 || t > keys[i - 1].time) && (i + 1 == keys.size() || t < keys[i + 1].time)) k.time = std::max(Ticks(0), t);
	}
}

void holdBilabials(const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys, Ticks frame) {
	const Ticks half(frame.count() / 2);
	std::vector<Keypose> out;
	out.reserve(keys.size() + 8);
	for (std::size_t i = 0; i < keys.size(); ++i) {
		const Keypose& k = keys[i];
		auto room = [&] {  // both copies half a frame from the keyposes either side, and not before 0
			return k.time >= half && (out.empty() || k.time - half - out.back().time >= half) &&
			       (i + 1 == keys.size() || keys[i + 1].time - (k.time + half) >= half);
		};
		if (!bilabial(k.cdv.label()) || !isPhoneKeypose(phones, k) || !room()) {
			out.push_back(k);
			continue;
		}
		Keypose a = k, b = k;
		a.time = k.time - half, b.time = k.time + half;
		out.push_back(a);
		out.push_back(b);
	}
	keys = std::move(out);
}

void applyVisualLead(const CoarticulationModel& m, std::vector<Keypose>& keys, Ticks frame) {
	if (!m.visualLead || keys.empty()) return;
	const Ticks lead = ticksFromSeconds(*m.visualLead);
	Ticks before{0}, moved{0};  // the keypose before: where it was and where it went
	for (std::size_t i = 0; i < keys.size(); ++i) {
		const Ticks was = keys[i].time;
		Ticks t = was + lead;
		if (i == 0) t = was <= Ticks(0) ? was : std::max(Ticks(0), t);
		else t = std::max(t, moved + std::min(was - before, frame));
		before = was, moved = t;
		keys[i].time = t;
	}
}

CoarticulationModel trainCoarticulation(const std::vector<CoarticulationClip>& clips, Ticks frame, double lambda) {
	std::vector<Eigen::MatrixXd> xs(clips.size()), ys(clips.size());
	for (std::size_t i = 0; i < clips.size(); ++i) coarticulationExamples(clips[i], frame, xs[i], ys[i]);
	CoarticulationModel m = fitCoarticulation(xs, ys, lambda);
	learnLeadingPause(m, clips);
	learnTrailingPause(m, clips);
	learnBilabialLead(m, clips, frame);
	return m;
}

void predictMouthOpenings(const CoarticulationModel& m, const std::vector<PhoneSegment>& phones, std::vector<Keypose>& keys) {
	if (m.features != coarticulationFeatureNames()) throw std::logic_error("predictMouthOpenings: the model's features are not this build's");
	std::vector<std::size_t> rows;
	const Eigen::MatrixXd X = coarticulationFeatures(phones, keys, rows);
	const Eigen::VectorXd y = (X * m.weights).array() + m.intercept, w = (X * m.widthWeights).array() + m.widthIntercept;
	for (Keypose& k : keys) {
		if (k.hold && m.leadOpening) k.mouthOpening = std::max(0.0, *m.leadOpening), k.mouthWidth = std::max(0.1, m.leadWidth.value_or(1.0));
		if (restKeypose(k) && m.restOpening) k.mouthOpening = std::max(0.0, *m.restOpening), k.mouthWidth = std::max(0.1, m.restWidth.value_or(1.0));
	}
	for (std::size_t r = 0; r < rows.size(); ++r) {
		keys[rows[r]].mouthOpening = std::max(0.0, y(Eigen::Index(r)));
		keys[rows[r]].mouthWidth = std::max(0.1, w(Eigen::Index(r)));
	}
}

void saveCoarticulation(const CoarticulationModel& m, const std::string& path) {
	std::ostringstream out;
	out << "# talkhead coarticulation model (D62): a keypose's inner-lip opening, in units of the speaker's 90th\n"
	    << "# percentile in speech, = intercept + Σ weight × feature (talkhead corpus coarticulation).\n";
	if (!m.source.empty()) out << "# learned from " << m.source << "\n";
	out << "talkhead-coarticulation\t" << (m.restOpening ? 5 : m.visualLead ? 4 : 3) << "\nlambda\t" << number(m.lambda) << "\nsamples\t" << m.samples << "\n";
	if (m.leadOpening)
		out << "# the lips held before the first words (pauses 'still'): opening, width, clips it is the mean of\nlead\t" << number(*m.leadOpening)
		    << "\t" << number(m.leadWidth.value_or(1.0)) << "\t" << m.leadClips << "\n";
	if (m.restOpening)
		out << "# the lips at rest after speech (a pause's rest): opening, width, clips it is the mean of\nrest\t" << number(*m.restOpening) << "\t"
		    << number(m.restWidth.value_or(1.0)) << "\t" << m.restClips << "\n";
	if (m.bilabialLead)
		out << "# /p b m/ shut this long after their keypose (s; < 0: before), closures it is the mean of\nbilabial\t" << number(*m.bilabialLead) << "\t"
		    << m.bilabialCount << "\n";
	if (m.visualLead)
		out << "# every keypose of aligned phones moved by this (s; < 0: earlier): the aligner's times come late (corpus-tools/visual-lead.sh)\nvisual\t"
		    << number(*m.visualLead) << "\n";
	out << "# name, weight for the opening, weight for the width\nintercept\t" << number(m.intercept) << "\t" << number(m.widthIntercept) << "\n";
	for (std::size_t i = 0; i < m.features.size(); ++i)
		out << "feature\t" << m.features[i] << "\t" << number(m.weights(Eigen::Index(i))) << "\t" << number(m.widthWeights(Eigen::Index(i))) << "\n";
	writeFileAtomically(path, out.str());
}

std::shared_ptr<const CoarticulationModel> shippedCoarticulation() {
	static const std::shared_ptr<const CoarticulationModel> m = [] {
		auto load = [](const char* name) {
			const auto path = findDataFile(name);
			if (!path) throw Error(std::string(name) + ": not found in the data folders (set TALKHEAD_DATA_DIR, or {{coarticulation}} off)");
			return loadCoarticulation(*path);
		};
		auto model = std::make_shared<CoarticulationModel>(load(kShippedCoarticulation));
		model->recognised = std::make_shared<const CoarticulationModel>(load(kShippedRecognisedCoarticulation));
		return std::shared_ptr<const CoarticulationModel>(std::move(model));
	}();
	return m;
}

std::shared_ptr<const CoarticulationModel> coarticulationOption(const std::string& value) {
	if (value == "off") return nullptr;
	if (value == "on") return shippedCoarticulation();
	return std::make_shared<const CoarticulationModel>(loadCoarticulation(value));
}

CoarticulationModel loadCoarticulation(const std::string& path) {
	std::ifstream in(path, std::ios::binary);
	if (!in) throw Error(path + ": cannot open the coarticulation model (" + std::strerror(errno) + ")");
	CoarticulationModel m;
	std::vector<double> weights, widthWeights;
	std::string line;
	long ln = 0;
	bool header = false, intercept = false;
	std::string version;
	while (std::getline(in, line)) {
		++ln;
		if (line.empty() || line[0] == '#') continue;
		const auto f = split(line, '\t');
		double v = 0;
		auto parse = [&](const std::string& s) {
			if (!parseDouble(s, v) || !std::isfinite(v)) throw Error(path, ln, "not a number: '" + s + "'");
			return v;
		};
		// A held mouth's line (lead, rest): opening, width (of the speaker's own), the clips it is the mean of.
		auto mouthLine = [&](const std::vector<std::string>& g, std::optional<double>& opening, std::optional<double>& width, std::size_t& clips) {
			opening = parse(g[1]);
			width = parse(g[2]);
			long long n = 0;
			if (!parseInt(g[3], n) || n < 1) throw Error(path, ln, g[0] + ": not a count of clips: '" + g[3] + "'");
			clips = std::size_t(n);
			if (*opening < 0 || *opening > 10 || *width <= 0 || *width > 10)
				throw Error(path, ln, g[0] + ": an opening or width out of range (0 … 10 of the speaker's own)");
		};
		if (!header) {
			if (f.size() != 2 || f[0] != "talkhead-coarticulation") throw Error(path, ln, "not a talkhead coarticulation model (expected 'talkhead-coarticulation 5')");
			if (f[1] != "1" && f[1] != "2" && f[1] != "3" && f[1] != "4" && f[1] != "5")
				throw Error(path, ln, "coarticulation model version " + f[1] + " (this build reads 1 to 5)");
			header = true, version = f[1];
		} else if (f[0] == "lead" && f.size() == 4 && version != "1" && !m.leadOpening) {
			mouthLine(f, m.leadOpening, m.leadWidth, m.leadClips);
		} else if (f[0] == "rest" && f.size() == 4 && version == "5" && !m.restOpening) {
			mouthLine(f, m.restOpening, m.restWidth, m.restClips);
		} else if (f[0] == "bilabial" && f.size() == 3 && (version == "3" || version == "4" || version == "5") && !m.bilabialLead) {
			m.bilabialLead = parse(f[1]);
			long long n = 0;
			if (!parseInt(f[2], n) || n < 1) throw Error(path, ln, "bilabial: not a count of closures: '" + f[2] + "'");
			m.bilabialCount = std::size_t(n);
			if (std::abs(*m.bilabialLead) > 0.1) throw Error(path, ln, "bilabial: a lead out of range (−0.1 … 0.1 s)");
		} else if (f[0] == "visual" && f.size() == 2 && (version == "4" || version == "5") && !m.visualLead) {
			m.visualLead = parse(f[1]);
			if (std::abs(*m.visualLead) > kMaxVisualLead) throw Error(path, ln, "visual: a lead out of range (−0.2 … 0.2 s)");
		} else if (f[0] == "lambda" && f.size() == 2) {
			m.lambda = parse(f[1]);
		} else if (f[0] == "samples" && f.size() == 2) {
			long long n = 0;
			if (!parseInt(f[1], n) || n < 0) throw Error(path, ln, "samples: not a count: '" + f[1] + "'");
			m.samples = std::size_t(n);
		} else if (f[0] == "intercept" && f.size() == 3) {
			m.intercept = parse(f[1]), m.widthIntercept = parse(f[2]), intercept = true;
		} else if (f[0] == "feature" && f.size() == 4) {
			m.features.push_back(f[1]);
			weights.push_back(parse(f[2]));
			widthWeights.push_back(parse(f[3]));
		} else {
			throw Error(path, ln, "unexpected line (expected lambda N, samples N, lead A B N (once, version 2 to 5), rest A B N (once, version 5), bilabial S N (once, version 3 to 5), visual S (once, version 4 or 5), intercept A B or feature NAME A B)");
		}
	}
	if (!header) throw Error(path + ": empty: not a talkhead coarticulation model");
	if (!intercept) throw Error(path + ": no intercept line: the file is cut short");
	if (m.features != coarticulationFeatureNames())
		throw Error(path + ": made for other features (" + std::to_string(m.features.size()) + " of them, this build has " +
		            std::to_string(coarticulationFeatureNames().size()) + "): train it again with 'talkhead corpus coarticulation'");
	m.weights = Eigen::Map<const Eigen::VectorXd>(weights.data(), Eigen::Index(weights.size()));
	m.widthWeights = Eigen::Map<const Eigen::VectorXd>(widthWeights.data(), Eigen::Index(widthWeights.size()));
	m.source = path;
	return m;
}

MouthFrame mouthFrame(const Scheme& scheme, const Points& p) {
	if (scheme.eyes.size() != 2 || scheme.mouth.empty()) throw std::logic_error("mouthFrame: the scheme has no eyes or no mouth line");
	auto centre = [&](const EyeSpec& e) -> Eigen::RowVector2d { return 0.5 * (p.row(e.corner0) + p.row(e.corner1)); };
	Eigen::RowVector2d a = centre(scheme.eyes[0]), b = centre(scheme.eyes[1]);
	if (a(0) > b(0)) std::swap(a, b);
	MouthFrame f;
	f.iod = (b - a).norm();
	if (!(f.iod > 0)) return {};
	f.across = (b - a) / f.iod, f.down = Eigen::RowVector2d(-f.across(1), f.across(0));
	f.centre.setZero();
	for (const auto& [up, low] : scheme.mouth.inner) f.centre += 0.5 * (p.row(up) + p.row(low));
	f.centre /= double(scheme.mouth.inner.size());
	return f;
}

MouthSize mouthSize(const Scheme& scheme, const Points& p) {
	const MouthFrame f = mouthFrame(scheme, p);
	if (!(f.iod > 0)) return {};
	MouthSize m;
	for (const auto& [up, down] : scheme.mouth.inner) m.opening += std::max(0.0, (p.row(down) - p.row(up)).dot(f.down));
	m.opening /= double(scheme.mouth.inner.size()) * f.iod;
	m.width = (p.row(scheme.mouth.corner1) - p.row(scheme.mouth.corner0)).norm() / f.iod;
	m.lift = (f.centre - 0.5 * (p.row(scheme.mouth.corner0) + p.row(scheme.mouth.corner1))).dot(f.down) / f.iod;
	return m;
}

void shutLips(const Scheme& scheme, Points& p) {
	const MouthFrame f = mouthFrame(scheme, p);
	if (!(f.iod > 0)) return;
	for (const auto& [up, down] : scheme.mouth.inner) {
		const double gap = (p.row(down) - p.row(up)).dot(f.down);
		if (!(gap > 0)) continue;
		p.row(up) += 0.5 * gap * f.down;
		p.row(down) -= 0.5 * gap * f.down;
	}
}

void drawOpening(const Scheme& scheme, Points& p, double opening) {
	const MouthFrame f = mouthFrame(scheme, p);
	const MouthSize now = mouthSize(scheme, p);
	if (!(f.iod > 0) || !(now.opening > 0) || !(opening >= 0)) return;
	const double stretch = std::min(opening / now.opening, now.opening >= kMinStretchOpening ? kMaxLipStretch : 1.0);
	if (std::abs(stretch - 1) < 1e-9) return;
	// Each lower inner lip's move, by its place across the face (u, in half mouth widths from the centre);
	// the corners stay.
	const double half = 0.5 * std::abs((p.row(scheme.mouth.corner1) - p.row(scheme.mouth.corner0)).dot(f.across));
	if (!(half > 0)) return;
	const Points before = p;
	const auto across = [&](Eigen::Index i) { return (before.row(i) - f.centre).dot(f.across) / half; };
	std::vector<std::pair<double, double>> move{{across(scheme.mouth.corner0), 0.0}, {across(scheme.mouth.corner1), 0.0}};
	std::vector<char> fixed(std::size_t(p.rows()), 0);
	fixed[std::size_t(scheme.mouth.corner0)] = fixed[std::size_t(scheme.mouth.corner1)] = 1;
	for (const auto& [up, down] : scheme.mouth.inner) {  // the upper lip stays, the lower one moves by the gap's change
		const double by = (stretch - 1) * std::max(0.0, (before.row(down) - before.row(up)).dot(f.down));
		move.push_back({across(down), by});
		p.row(down) += by * f.down;
		fixed[std::size_t(up)] = fixed[std::size_t(down)] = 1;
	}
	std::sort(move.begin(), move.end());
	const auto moveAt = [&](double u) {
		if (u <= move.front().first || u >= move.back().first) return 0.0;
		const auto hi = std::upper_bound(move.begin(), move.end(), std::make_pair(u, -1e300));
		const auto lo = hi - 1;
		const double t = hi->first > lo->first ? (u - lo->first) / (hi->first - lo->first) : 0.0;
		return lo->second + t * (hi->second - lo->second);
	};
	for (Eigen::Index i = 0; i < p.rows(); ++i) {
		if (fixed[std::size_t(i)]) continue;
		const double v = (before.row(i) - f.centre).dot(f.down) / f.iod;
		if (!(v > 0) || v >= 2.5) continue;  // above the mouth, or well below the chin
		const double fade = v <= 1.5 ? 1.0 : 2.5 - v;
		p.row(i) += fade * moveAt(across(i)) * f.down;
	}
}

bool mouthScheme(const FaceModel& model, Scheme& out) {
	out = model.scheme;  // a loaded model's parts come from its shipped scheme (completeSchemeParts)
	return out.eyes.size() == 2 && !out.mouth.empty();
}

std::vector<MouthSize> sampleMouths(const FaceModel& model, const Scheme& scheme) {
	std::vector<MouthSize> size(model.sampleCount());
	for (std::size_t s = 0; s < model.sampleCount(); ++s) size[s] = mouthSize(scheme, model.alignedShapes[s]);
	return size;
}

MouthPool mouthPool(const FaceModel& model, const std::vector<MouthSize>& size, const std::string& emotion) {
	MouthPool p;
	std::vector<double> open, width;
	for (std::size_t s = 0; s < model.sampleCount(); ++s)
		if (model.samples[s].emotion == emotion) {
			p.samples.push_back(s);
			if (model.samples[s].cdv != "sil") open.push_back(size[s].opening), width.push_back(size[s].width);
		}
	if (!open.empty()) {
		std::vector<double> sorted = open;
		std::sort(sorted.begin(), sorted.end());
		p.scale = sorted[std::size_t(0.9 * double(sorted.size() - 1))];
		p.closedLimit = sorted.front() + 0.1 * (sorted.back() - sorted.front());  // issue 32: ≤ 10 % of the open range
		p.widest = sorted.back();
		double mw = 0, sw = 0;
		for (double w : width) mw += w;
		mw /= double(width.size());
		for (double w : width) sw += (w - mw) * (w - mw);
		p.widthSpread = std::sqrt(sw / double(width.size())) + 1e-6;
		double mo = 0, so = 0, sow = 0;  // width = a + b · opening (open, width are in sample order here)
		for (double o : open) mo += o;
		mo /= double(open.size());
		for (std::size_t i = 0; i < open.size(); ++i) so += (open[i] - mo) * (open[i] - mo), sow += (open[i] - mo) * (width[i] - mw);
		p.widthPerOpening = so > 1e-12 ? sow / so : 0.0;
		p.widthAtShut = mw - p.widthPerOpening * mo;
		std::sort(width.begin(), width.end());
		p.width = width[width.size() / 2];
	}
	return p;
}

namespace {
constexpr double kPeakShare = 0.87;
double mouthCost(const MouthPool& pool, const MouthSize& m, double opening, double width) {
	const double dOpen = (m.opening - opening) / pool.scale, dWidth = (m.width - width) / pool.widthSpread;
	return dOpen * dOpen + kWidthWeight * dWidth * dWidth;
}
}  // namespace

double openingUnit(const MouthPool& pool, const MouthPool& neutral) {
	const double norm = kPeakShare * (neutral.widest > 0 ? neutral.widest : pool.widest);
	return kPeakShare * pool.widest * (norm > kSpeakersOpening ? kSpeakersOpening / norm : 1.0);
}

long nearestMouth(const FaceModel& model, const MouthPool& pool, const std::vector<MouthSize>& size, double opening, double width, long prefer) {
	long best = -1;
	double least = std::numeric_limits<double>::max();
	if (prefer >= 0) best = prefer, least = mouthCost(pool, size[std::size_t(prefer)], opening, width);
	for (std::size_t s : pool.samples) {
		if (model.samples[s].cdv == "sil") continue;
		const double cost = mouthCost(pool, size[s], opening, width);
		if (cost < least) least = cost, best = long(s);
	}
	return best;
}

std::size_t chooseMouthExemplars(const FaceModel& model, const Emotion& emotion, std::vector<Keypose>& keys) {
	Scheme scheme;
	if (!mouthScheme(model, scheme)) {  // no mouth to measure: the predictions cannot choose, the fallbacks draw
		for (Keypose& k : keys)
			if (k.sample < 0) k.mouthOpening.reset(), k.mouthWidth.reset();
		return 0;
	}
	const std::vector<MouthSize> size = sampleMouths(model, scheme);
	// Per emotion: its samples and this face's scale (the 90th percentile of their openings, pauses left out).
	std::map<std::string, MouthPool> pools;
	auto poolOf = [&](const std::string& e) -> const MouthPool& {
		auto it = pools.find(e);
		if (it != pools.end()) return it->second;
		return pools.emplace(e, mouthPool(model, size, e)).first->second;
	};
	std::size_t chosen = 0;
	for (Keypose& k : keys) {
		if (!k.mouthOpening || k.sample >= 0) continue;
		std::string e = k.emotion.value_or(emotion).label();
		if (poolOf(e).samples.empty() || !(poolOf(e).scale > 0)) e = Emotion::neutralLabel();
		const MouthPool& pool = poolOf(e);
		if (pool.samples.empty() || !(pool.scale > 0)) {  // nothing to choose from: the synthesizer's fallbacks
			k.mouthOpening.reset(), k.mouthWidth.reset();
			continue;
		}
		if (restKeypose(k)) {
			// D107: the rest is the face's own rest mouth, drawn no more open than speakers rest after speaking.
			// The speakers were neutral: what the face's neutral rest opens beyond their rest (on its unit) is
			// taken off every emotion's rest, so an expression's open mouth (surprise's dropped jaw) keeps what
			// it adds. A shut neutral rest (within its pool's closed limit) leaves every rest as it is, and so
			// does an emotion with no rest of its own: the synthesizer's fallbacks.
			const std::string& neutral = Emotion::neutralLabel();
			const long rest = model.findSample(e, k.cdv.label(), &k.context);
			const long own = model.findSample(neutral, k.cdv.label(), &k.context);
			const bool byNeutral = own >= 0 && poolOf(neutral).scale > 0;
			const MouthPool& calm = byNeutral ? poolOf(neutral) : pool;
			const long ref = byNeutral ? own : rest;
			const double target = *k.mouthOpening * openingUnit(calm, poolOf(neutral));
			const double excess = ref >= 0 && size[std::size_t(ref)].opening > std::max(target, calm.closedLimit) ? size[std::size_t(ref)].opening - target : 0;
			if (rest >= 0 && excess > 0) k.sample = rest, k.drawnOpening = std::max(0.0, size[std::size_t(rest)].opening - excess), ++chosen;
			else k.mouthOpening.reset(), k.mouthWidth.reset();
			continue;
		}
		// The emotion's own exemplar of the CDV; one it lacks (a short take: issue 47) is chosen from the
		// emotion's whole pool by the predicted mouth like any other — not left to the synthesizer's
		// fallbacks, which know nothing of the prediction.
		const long own = model.findSample(e, k.cdv.label(), &k.context);
		const MouthSize* o = own >= 0 ? &size[std::size_t(own)] : nullptr;
		long best = own;
		if (bilabial(k.cdv.label())) {
			if (!o || o->opening > pool.closedLimit) {
				const double above = o ? o->opening : std::numeric_limits<double>::max();
				double least = std::numeric_limits<double>::max();
				for (int pass = 0; pass < 2 && best == own; ++pass)  // a bilabial exemplar first, then any
					for (std::size_t s : pool.samples)
						if ((pass == 1 || bilabial(model.samples[s].cdv)) && size[s].opening < least && size[s].opening < above)
							least = size[s].opening, best = long(s);
			}
		} else {
			// The prediction is in units of the speakers' 90th percentile of openings over every frame of
			// their speech. The face's samples are keyposes, each its viseme's extreme: its widest stands for
			// a speaker's widest, and the GRID speakers' 90th percentile is kPeakShare of their widest (median
			// over the 95 clips the shipped model learned from). The 90th percentile of the samples was the
			// unit before: a face with few open samples (a short take, a small corpus) never reached them (D90).
			// A face that opens wider than speakers do is scaled to them (D105).
			const double target = *k.mouthOpening * openingUnit(pool, poolOf(Emotion::neutralLabel()));
			// The predicted width is the speakers' relative to their median; the face's is taken relative to
			// its usual width at the target opening (D90), so a face whose open mouths are all wider than its
			// median (franck) still opens.
			const double width = k.mouthWidth ? *k.mouthWidth * pool.usualWidth(target) : (o ? o->width : pool.width);
			const long nearest = nearestMouth(model, pool, size, target, width);
			// The exemplar is the nearest sample; the opening is drawn as predicted (D100).
			if (nearest >= 0) best = nearest, k.drawnOpening = target;
		}
		if (best < 0) {  // no exemplar at all (a pool of pauses): the synthesizer's fallbacks, unpredicted
			k.mouthOpening.reset(), k.mouthWidth.reset();
			continue;
		}
		k.sample = best;
		++chosen;
	}
	return chosen;
}

}  // namespace talkhead
