// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/face_build.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "align/align.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "corpus/build.h"
#include "corpus/corpus.h"
#include "media/video_reader.h"
#include "model/model_file.h"
#include "phonetics/labels.h"
#include "phonetics/transcript.h"

namespace fs = std::filesystem;

namespace talkhead {

namespace {

// The phones of a take's speech (and its words, where known): its transcript, or its text aligned to the
// audio (the video's own track, or the take's audio).
std::vector<PhoneSegment> takeSpeech(const VideoTake& take, const VideoInfo& info, const Language& lang, std::vector<Interval>& words, TakeSpeechNote* note) {
	Transcript phoneTranscript;
	if (!take.transcript.empty()) {
		phoneTranscript = readTranscript(take.transcript);
	} else {
		const std::string audio = take.audio.empty() ? take.video : take.audio;
		if (take.audio.empty() && !info.hasAudio) throw Error(take.video, 0, "has no audio track to align the text with (give its audio, or choose frames by shape)");
		AlignOptions ao;
		ao.languageTag = lang.tag();
		Alignment a = alignSpeechFile(audio, take.text, ao);
		if (note) {
			note->alignConfidence = a.confidence;
			note->alignedAudio = audio;
			note->warnings.insert(note->warnings.end(), a.warnings.begin(), a.warnings.end());
		}
		phoneTranscript = a.phones;
		words = a.words.intervals;
	}
	if (phoneTranscript.level == LabelLevel::Word) words = phoneTranscript.intervals;
	// An alignment's phones are canonical IPA; a transcript's notation is decided from its labels. Times in
	// the transcript are relative to the audio, which starts with the video.
	return phoneSegments(phoneTranscript, lang, UnknownPhone::Error, take.transcript.empty() ? Notation::Ipa : Notation::Auto);
}

// Progress over [from, to) of a caller's.
class SubProgress final : public ProgressSink {
public:
	SubProgress(ProgressSink& outer, double from, double to, std::string prefix) : outer_(outer), from_(from), to_(to), prefix_(std::move(prefix)) {}
	void report(double fraction, const std::string& stage) override { outer_.report(from_ + (to_ - from_) * fraction, prefix_ + stage); }

private:
	ProgressSink& outer_;
	double from_, to_;
	std::string prefix_;
};

// An exclusive lock on a file, released when destroyed.
class FileLock {
public:
	explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
		if (fd_ < 0) throw Error(path, 0, "cannot open the lock file for building a face");
		while (::flock(fd_, LOCK_EX) != 0)
			if (errno != EINTR) throw Error(path, 0, "cannot lock the face being built");
	}
	~FileLock() { ::close(fd_); }
	FileLock(const FileLock&) = delete;
	FileLock& operator=(const FileLock&) = delete;

private:
	int fd_;
};

// The takes written as one corpus in `scratch` (made here, removed after), built with `build`'s defaults.
FaceModel buildFromPlans(const std::vector<TakePlan>& plans, std::size_t base, const fs::path& scratch, ProgressSink& progress, double from,
                         std::vector<ColourMatch>* colours = nullptr) {
	std::error_code ec;
	fs::remove_all(scratch, ec);
	struct Remove {
		fs::path p;
		~Remove() {
			std::error_code e;
			fs::remove_all(p, e);
		}
	} remove{scratch};
	fs::create_directories(scratch, ec);
	if (ec) throw Error(scratch.string(), 0, "cannot make the scratch folder for the face (" + ec.message() + ")");
	progress.report(from, "writing the corpus");
	// PNG level 1: the scratch folder is read once and removed; level 6 took a third of a face's build (D102).
	std::vector<ColourMatch> m = writeTakesCorpus(plans, base, scratch.string(), 1);
	if (colours) *colours = std::move(m);
	const Corpus corpus = loadCorpus((scratch / "corpus.csv").string());
	const Scheme scheme = corpusScheme(corpus, corpus.schemeName);
	SubProgress sub(progress, from, 1.0, "");
	return buildFaceModel(corpus, scheme, BuildOptions{}, sub);
}

// Progress of takes planned at once: the mean of their fractions over [0, share) of the caller's.
class TakesProgress {
public:
	TakesProgress(ProgressSink& outer, std::size_t takes, double share) : outer_(outer), done_(takes, 0.0), share_(share) {}
	void report(std::size_t take, double fraction, const std::string& stage) {
		const std::lock_guard<std::mutex> lock(mutex_);
		done_[take] = fraction;
		double sum = 0;
		for (double d : done_) sum += d;
		outer_.report(share_ * sum / double(done_.size()), "take " + std::to_string(take + 1) + " of " + std::to_string(done_.size()) + ": " + stage);
	}

private:
	ProgressSink& outer_;
	std::vector<double> done_;
	double share_;
	std::mutex mutex_;
};

class TakeProgress final : public ProgressSink {
public:
	TakeProgress(TakesProgress& all, std::size_t take) : all_(all), take_(take) {}
	void report(double fraction, const std::string& stage) override { all_.report(take_, fraction, stage); }

private:
	TakesProgress& all_;
	std::size_t take_;
};

// The takes of a shipped face planned two at a time on a machine with two cores (each thread with its own
// dlib model, loaded once, not once per take): tracking is most of a face's build (D102). Takes whose text
// must be aligned are planned one at a time — libespeak-ng is one state per process. The plans, and so the
// model, do not depend on the number of threads: each take is planned alone, into its own slot.
std::vector<TakePlan> planTakesAtOnce(const std::vector<VideoTake>& takes, const Language& lang, bool byShape, ProgressSink& progress, double share) {
	bool aligns = false;
	for (const auto& t : takes)
		if (!byShape && t.transcript.empty()) aligns = true;
	const std::size_t threads = aligns ? 1 : std::min<std::size_t>({2, takes.size(), std::max(1u, std::thread::hardware_concurrency())});
	std::vector<std::optional<TakePlan>> plans(takes.size());
	std::vector<std::exception_ptr> errors(takes.size());
	TakesProgress all(progress, takes.size(), share);
	std::atomic<std::size_t> next{0};
	std::atomic<bool> failed{false};
	auto work = [&] {
		std::optional<FaceLandmarker> landmarker;
		for (std::size_t k; !failed && (k = next++) < takes.size();) {
			try {
				if (!landmarker) landmarker.emplace();
				TakeProgress sub(all, k);
				plans[k] = planVideoTake(takes[k], lang, FromVideoOptions{}, byShape, "", sub, nullptr, {}, &*landmarker);
			} catch (...) {
				errors[k] = std::current_exception();
				failed = true;
			}
		}
	};
	std::vector<std::thread> pool;
	for (std::size_t i = 1; i < threads; ++i) pool.emplace_back(work);
	work();
	for (auto& t : pool) t.join();
	for (const auto& e : errors)  // the first take that failed, as planning them in order would report it
		if (e) std::rethrow_exception(e);
	std::vector<TakePlan> out;
	for (auto& p : plans) out.push_back(std::move(*p));
	return out;
}

}  // namespace

TakePlan planVideoTake(const VideoTake& take, const Language& lang, const FromVideoOptions& options, bool byShape, const std::string& landmarksTsv,
                       ProgressSink& progress, TakeSpeechNote* note, const FrameCallback& onFrame, FaceLandmarker* landmarker) {
	TakePlan tp;
	tp.take = take;
	VideoInfo info;
	{
		VideoReader probe(take.video);
		info = probe.info();
	}
	std::vector<PhoneSegment> phones;
	std::vector<Interval> words;
	if (!byShape) phones = takeSpeech(take, info, lang, words, note);
	if (!landmarksTsv.empty()) {
		tp.track = readLandmarksTsv(landmarksTsv);
		tp.track.info = info;
	} else {
		TrackOptions to;
		to.landmarker = landmarker;
		to.start = take.start;
		if (take.duration > Ticks(0)) to.duration = take.duration;
		tp.track = trackVideo(take.video, to, progress, onFrame);
	}
	FromVideoOptions fo = options;
	fo.emotion = take.emotion;
	tp.plan = byShape ? selectByShape(tp.track, loadCdvMouthTargets(), fo) : selectByPhones(tp.track, phones, words, fo);
	return tp;
}

std::size_t basefaceTake(const std::vector<TakePlan>& plans) {
	for (std::size_t k = 0; k < plans.size(); ++k)
		if (plans[k].take.emotion == Emotion::neutralLabel()) return k;
	return 0;
}

std::string ensureShippedFace(const ShippedFace& face, ProgressSink& progress) {
	if (auto built = builtShippedFace(face)) return *built;
	const std::string model = shippedFaceModelPath(face);
	if (model.empty()) throw Error("cannot build the face '" + face.name + "': no cache folder to keep it in (set XDG_CACHE_HOME or HOME)");
	const fs::path folder = fs::path(model).parent_path();
	std::error_code ec;
	fs::create_directories(folder, ec);
	if (ec) throw Error(folder.string(), 0, "cannot make the folder for the face '" + face.name + "' (" + ec.message() + ")");
	FileLock lock((folder / (face.name + ".lock")).string());
	if (auto built = builtShippedFace(face)) return *built;  // another process built it while this one waited

	const std::vector<VideoTake> takes = readTakeList(face.takes);
	const Language& lang = Language::get(face.lang);
	bool byShape = true;
	for (const auto& t : takes)
		if (!t.transcript.empty() || !t.text.empty()) byShape = false;
	const double trackShare = 0.75;
	const std::vector<TakePlan> plans = planTakesAtOnce(takes, lang, byShape, progress, trackShare);
	const FaceModel m = buildFromPlans(plans, basefaceTake(plans), folder / (face.name + "-corpus.tmp"), progress, trackShare);
	const fs::path recipe = fs::path(model).replace_extension(".recipe");
	fs::remove(recipe, ec);  // a model never stands beside another recipe's stamp
	saveModel(m, model);
	writeFileAtomically(recipe.string(), shippedFaceRecipe(face));
	return model;
}

FaceLook faceLook(const Image8& rgb, const Points& p) {
	FaceLook look;
	if (rgb.empty() || p.rows() != kIbugPoints || rgb.channels != 3) return look;
	const double iod = std::hypot(p(45, 0) - p(36, 0), p(45, 1) - p(36, 1));
	if (!(iod > 4)) return look;
	double x0 = p.col(0).minCoeff(), x1 = p.col(0).maxCoeff(), y0 = p.col(1).minCoeff(), y1 = p.col(1).maxCoeff();
	const int left = std::max(0, int(std::floor(x0))), top = std::max(0, int(std::floor(y0)));
	const int right = std::min(rgb.width, int(std::ceil(x1)) + 1), bottom = std::min(rgb.height, int(std::ceil(y1)) + 1);
	if (right - left < 8 || bottom - top < 8) return look;
	const cv::Mat whole(rgb.height, rgb.width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data.data()));
	cv::Mat grey, scaled, lap;
	cv::cvtColor(whole(cv::Rect(left, top, right - left, bottom - top)), grey, cv::COLOR_RGB2GRAY);
	const double s = 64.0 / iod;
	cv::resize(grey, scaled, cv::Size(), s, s, s < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
	std::vector<cv::Point> pts, hull;
	for (Eigen::Index i = 0; i < p.rows(); ++i) pts.emplace_back(int(std::lround((p(i, 0) - left) * s)), int(std::lround((p(i, 1) - top) * s)));
	cv::convexHull(pts, hull);
	cv::Mat mask = cv::Mat::zeros(scaled.rows, scaled.cols, CV_8U);
	cv::fillConvexPoly(mask, hull, cv::Scalar(255));
	look.luma = cv::mean(scaled, mask)[0];
	cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), 2);  // the outline's own edge is not detail
	cv::Laplacian(scaled, lap, CV_32F, 1);
	cv::Scalar mean, sd;
	cv::meanStdDev(lap, mean, sd, mask);
	look.detail = std::sqrt(sd[0] * sd[0] + mean[0] * mean[0]);
	return look;
}

TakeCensus takeCensus(const LandmarkTrack& track, const std::vector<FaceLook>& looks, const FromVideoOptions& o) {
	TakeCensus c;
	c.video = track.source;
	c.seen = track.frames.size();
	const double fps = track.info.fpsNum > 0 && track.info.fpsDen > 0 ? double(track.info.fpsNum) / track.info.fpsDen : 25;
	c.seconds = double(c.seen) / fps;
	std::vector<double> eyes, luma, detail, opening;
	std::vector<std::size_t> confident;
	for (std::size_t i = 0; i < track.frames.size(); ++i) {
		const FrameLandmarks& f = track.frames[i];
		if (f.faces >= 0) ++c.detections, c.severalFaces += f.faces > 1;
		if (!f.found) continue;
		++c.found;
		if (i < looks.size() && looks[i].luma > 0) luma.push_back(looks[i].luma), detail.push_back(looks[i].detail);
		opening.push_back(mouthMeasures(f.points).opening);
		if (f.confidence < o.minConfidence) {
			++c.lowConfidence;
			continue;
		}
		confident.push_back(i);
		const double e = eyeAspect(f.points);
		if (std::isfinite(e)) eyes.push_back(e);
	}
	c.faceSeconds = double(c.found) / fps;
	const double minEyes = o.minEyeOpening * percentile(eyes, 0.5), maxRoll = o.maxRollDegrees * M_PI / 180;
	std::vector<std::size_t> open;
	for (std::size_t i : confident) {
		const Points& p = track.frames[i].points;
		if (std::abs(headRoll(p)) > maxRoll || std::abs(headYaw(p)) > o.maxYaw) ++c.turned;
		else if (!(eyeAspect(p) >= minEyes)) ++c.blinks;
		else open.push_back(i);
	}
	if (!open.empty()) {
		std::vector<double> o2, l2;
		for (std::size_t i : open) o2.push_back(mouthMeasures(track.frames[i].points).opening), l2.push_back(cornerLift(track.frames[i].points));
		const UsualLift usual(o2, l2);
		for (std::size_t k = 0; k < open.size(); ++k)
			if ((l2[k] - usual.at(o2[k])) / usual.spread() > 2) ++c.smiles;
			else ++c.usable;
	}
	c.brightness = percentile(luma, 0.5);
	c.brightnessDrift = c.brightness > 0 ? (percentile(luma, 0.95) - percentile(luma, 0.05)) / c.brightness : 0;
	c.detail = percentile(detail, 0.5);
	c.openingRange = percentile(opening, 0.95) - percentile(opening, 0.05);
	return c;
}

std::optional<std::string> takeRefusal(const TakeCensus& c, const FaceCreateLimits& l) {
	char buf[400];
	if (c.detections > 0 && double(c.severalFaces) > l.maxSeveralFaces * double(c.detections)) {
		std::snprintf(buf, sizeof buf, "several faces (in %zu of %zu detections): film one person, alone in the frame", c.severalFaces, c.detections);
		return c.video + ": " + buf;
	}
	if (c.faceSeconds < l.minFaceSeconds) {
		std::snprintf(buf, sizeof buf, "too short: a face in %.1f s of video (at least %.1f s a take, %.0f s in all; 20 s or more of speech covers the visemes)",
		              c.faceSeconds, l.minFaceSeconds, l.minTotalFaceSeconds);
		return c.video + ": " + buf;
	}
	if (c.found > 0 && double(c.turned) > l.maxTurned * double(c.found)) {
		std::snprintf(buf, sizeof buf, "the head is turned or tilted in %.0f %% of the frames: face the camera", 100.0 * double(c.turned) / double(c.found));
		return c.video + ": " + buf;
	}
	if (c.brightness > 0 && c.brightness < l.minBrightness) {
		std::snprintf(buf, sizeof buf, "too dark (the face's brightness %.0f of 255; at least %.0f): more light on the face", c.brightness, l.minBrightness);
		return c.video + ": " + buf;
	}
	if (c.detail > 0 && c.detail < l.minDetail) {
		std::snprintf(buf, sizeof buf, "too blurred (the face's detail %.2f; at least %.2f): focus, more light, a steadier camera", c.detail, l.minDetail);
		return c.video + ": " + buf;
	}
	return std::nullopt;
}

FaceCreateReport createFace(const std::vector<VideoTake>& takes, const FaceCreateOptions& options, const std::string& modelPath, ProgressSink& progress) {
	if (takes.empty()) throw Error("no video to make a face from");
	FaceCreateReport report;
	const Language& lang = Language::get(options.lang);
	std::vector<TakePlan> plans;
	const double trackShare = 0.8;
	for (const VideoTake& take : takes) {
		const double k = double(plans.size()), n = double(takes.size());
		SubProgress sub(progress, trackShare * k / n, trackShare * (k + 1) / n,
		                takes.size() > 1 ? "take " + std::to_string(plans.size() + 1) + " of " + std::to_string(takes.size()) + ": " : "");
		std::vector<FaceLook> looks;
		const bool byShape = take.transcript.empty() && take.text.empty();
		TakePlan tp = planVideoTake(take, lang, options.selection, byShape, "", sub, nullptr, [&](const FrameLandmarks& f, const Image8& rgb) {
			looks.push_back(f.found ? faceLook(rgb, f.points) : FaceLook{});
		});
		TakeCensus census = takeCensus(tp.track, looks, options.selection);
		census.video = take.video;
		if (auto refusal = takeRefusal(census, options.limits)) throw Error(*refusal);
		report.takes.push_back(census);
		report.methods.push_back(tp.plan.method);
		report.emotions.push_back(take.emotion);
		report.ownBlink = report.ownBlink || tp.plan.closedEyes.has_value();
		plans.push_back(std::move(tp));
	}
	double total = 0;
	for (const auto& c : report.takes) total += c.faceSeconds;
	if (total < options.limits.minTotalFaceSeconds) {
		char buf[300];
		std::snprintf(buf, sizeof buf, ": too short: a face in %.1f s of video in all (at least %.0f s; 20 s or more of speech covers the visemes)", total,
		              options.limits.minTotalFaceSeconds);
		throw Error(takes.front().video + buf);
	}
	// Coverage over all takes, in visemes.tsv's order.
	std::map<std::string, int> frames;
	for (const auto& p : plans)
		for (const auto& e : p.plan.entries) ++frames[e.cdv];
	for (const auto& v : visemeLabels()) {
		auto it = frames.find(v.label);
		if (it != frames.end()) report.cdvFrames.emplace_back(v.label, it->second);
		else report.missing.push_back(v.label);
	}
	if (report.cdvFrames.size() < options.limits.minCdvs)
		throw Error(takes.front().video + ": too little speech: frames for " + std::to_string(report.cdvFrames.size()) + " of " +
		            std::to_string(visemeLabels().size()) + " visemes (at least " + std::to_string(options.limits.minCdvs) +
		            "): record 20 s or more of varied speech");
	// The corpus in a scratch folder beside the model, built, saved; the folder goes.
	const fs::path out(modelPath);
	report.baseTake = basefaceTake(plans);
	const FaceModel m = buildFromPlans(plans, report.baseTake, (out.parent_path().empty() ? fs::path(".") : out.parent_path()) / (out.filename().string() + ".corpus.tmp"),
	                                   progress, trackShare, &report.colours);
	saveModel(m, modelPath);
	report.samples = m.sampleCount();
	// What would make it better.
	double faceSeconds = 0, range = 0, bright = 1e9, drift = 0, turned = 0, found = 0;
	for (const auto& c : report.takes) {
		faceSeconds += c.faceSeconds, range = std::max(range, c.openingRange), bright = std::min(bright, c.brightness), drift = std::max(drift, c.brightnessDrift);
		turned += double(c.turned), found += double(c.found);
	}
	char buf[400];
	if (report.missing.size() > 8 || faceSeconds < 20) {
		std::snprintf(buf, sizeof buf, "record %.0f s more of varied speech (%zu of %zu visemes have no frame of their own)", std::max(20.0, 60.0 - faceSeconds),
		              report.missing.size(), visemeLabels().size());
		report.advice.push_back(buf);
	}
	if (range < 0.12) {
		std::snprintf(buf, sizeof buf, "record 20 s more with your mouth wide open (its opening spans %.2f eye distances; people speaking span about 0.17)", range);
		report.advice.push_back(buf);
	}
	if (bright < 90) {
		std::snprintf(buf, sizeof buf, "more light (the face's brightness is %.0f of 255)", bright);
		report.advice.push_back(buf);
	}
	if (drift > 0.15) {
		std::snprintf(buf, sizeof buf, "steadier light (the face's brightness varies %.0f %% within a take)", 100 * drift);
		report.advice.push_back(buf);
	}
	if (found > 0 && turned > 0.2 * found) {
		std::snprintf(buf, sizeof buf, "face the camera (the head is turned or tilted in %.0f %% of the frames)", 100 * turned / found);
		report.advice.push_back(buf);
	}
	if (!report.ownBlink) report.advice.push_back("blink once or twice with your head still and your mouth at rest (blinks now draw the lid)");
	return report;
}

}  // namespace talkhead
