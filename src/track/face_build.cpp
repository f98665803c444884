// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/face_build.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>

#include "align/align.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "corpus/build.h"
#include "corpus/corpus.h"
#include "media/video_reader.h"
#include "model/model_file.h"
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

}  // namespace

TakePlan planVideoTake(const VideoTake& take, const Language& lang, const FromVideoOptions& options, bool byShape, const std::string& landmarksTsv,
                       ProgressSink& progress, TakeSpeechNote* note) {
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
		to.start = take.start;
		if (take.duration > Ticks(0)) to.duration = take.duration;
		tp.track = trackVideo(take.video, to, progress);
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
	std::vector<TakePlan> plans;
	const double trackShare = 0.75;
	for (const VideoTake& take : takes) {
		const double k = double(plans.size()), n = double(takes.size());
		SubProgress sub(progress, trackShare * k / n, trackShare * (k + 1) / n,
		                "take " + std::to_string(plans.size() + 1) + " of " + std::to_string(takes.size()) + ": ");
		plans.push_back(planVideoTake(take, lang, FromVideoOptions{}, byShape, "", sub));
	}
	const fs::path corpusDir = folder / (face.name + "-corpus.tmp");
	fs::remove_all(corpusDir, ec);
	struct Remove {
		fs::path p;
		~Remove() {
			std::error_code e;
			fs::remove_all(p, e);
		}
	} remove{corpusDir};
	fs::create_directories(corpusDir, ec);
	if (ec) throw Error(corpusDir.string(), 0, "cannot make the scratch folder for the face '" + face.name + "' (" + ec.message() + ")");
	progress.report(trackShare, "writing the corpus");
	writeTakesCorpus(plans, basefaceTake(plans), corpusDir.string());
	const Corpus corpus = loadCorpus((corpusDir / "corpus.csv").string());
	const Scheme scheme = corpusScheme(corpus, corpus.schemeName);
	SubProgress sub(progress, trackShare, 1.0, "");
	const FaceModel m = buildFaceModel(corpus, scheme, BuildOptions{}, sub);
	const fs::path recipe = fs::path(model).replace_extension(".recipe");
	fs::remove(recipe, ec);  // a model never stands beside another recipe's stamp
	saveModel(m, model);
	writeFileAtomically(recipe.string(), shippedFaceRecipe(face));
	return model;
}

}  // namespace talkhead
