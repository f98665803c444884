// SPDX-License-Identifier: GPL-3.0-or-later
#include "track/landmarks.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/plugin.h"
#include "base/text.h"
#include "corpus/landmarks_tsv.h"
#include "geometry/scheme.h"
#include "media/image_io.h"
#include "track/from_video.h"

namespace talkhead {

namespace fs = std::filesystem;

namespace {

const DlibModule& dlibModule() {
	static const auto* m = static_cast<const DlibModule*>(loadPlugin("libtalkhead-dlib.so", "talkhead_dlib_module", kDlibModuleAbi));
	return *m;
}

constexpr double kCropBoxWidth = 240;  // the face box's width in the image the predictor sees

// Where a detector box sits relative to the 68 points: offsets of its sides from the points' centroid in
// units of their RMS radius (learnt from each detection; this default is dlib's typical frontal box).
struct BoxRelation {
	double left = -1.45, top = -1.05, right = 1.45, bottom = 1.85;
};

void centroidRadius(const Points& p, double& cx, double& cy, double& r) {
	cx = p.col(0).mean();
	cy = p.col(1).mean();
	double s = 0;
	for (Eigen::Index i = 0; i < p.rows(); ++i) s += (p(i, 0) - cx) * (p(i, 0) - cx) + (p(i, 1) - cy) * (p(i, 1) - cy);
	r = std::sqrt(s / double(std::max<Eigen::Index>(1, p.rows())));
}

BoxRelation relationOf(const FaceBox& b, const Points& p) {
	double cx, cy, r;
	centroidRadius(p, cx, cy, r);
	if (r <= 0) return {};
	return {(b.left - cx) / r, (b.top - cy) / r, (b.right - cx) / r, (b.bottom - cy) / r};
}

FaceBox boxFrom(const Points& p, const BoxRelation& rel) {
	double cx, cy, r;
	centroidRadius(p, cx, cy, r);
	return {cx + rel.left * r, cy + rel.top * r, cx + rel.right * r, cy + rel.bottom * r, 0};
}

double overlap(const FaceBox& a, const FaceBox& b) {
	const double w = std::min(a.right, b.right) - std::max(a.left, b.left), h = std::min(a.bottom, b.bottom) - std::max(a.top, b.top);
	if (w <= 0 || h <= 0) return 0;
	const double i = w * h;
	return i / (a.width() * a.height() + b.width() * b.height() - i);
}

bool isImageFile(const fs::path& p) {
	std::string e = p.extension().string();
	for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
	return e == ".jpg" || e == ".jpeg" || e == ".png" || e == ".bmp" || e == ".tif" || e == ".tiff" || e == ".ppm" || e == ".pgm";
}

// Per-frame tracking state shared by video and image input.
class Tracker {
public:
	Tracker(FaceLandmarker& lm, const TrackOptions& o) : lm_(lm), o_(o) {}

	// A fit and its consistency: a second fit from the box the first one implies; the points are the mean
	// of the two, the confidence falls linearly to 0 at a disagreement of 8 % of the eye distance.
	// `first`: the fit from `box`, when the caller has it already.
	bool fitChecked(const Image8& grey, const FaceBox& box, Points& out, double& confidence, const Points* first = nullptr) {
		const Points a = first ? *first : lm_.fit(grey, box);
		const Points b = lm_.fit(grey, boxFrom(a, rel_));
		const double iod = eyeDistance(a);
		if (!(iod > 2)) return false;
		const double d = (a - b).rowwise().norm().mean() / iod;
		confidence = std::clamp(1.0 - d / 0.08, 0.0, 1.0);
		out = 0.5 * (a + b);
		// A face must lie inside the frame (mostly) and be of a plausible size.
		double cx, cy, r;
		centroidRadius(out, cx, cy, r);
		if (cx < 0 || cy < 0 || cx >= grey.width || cy >= grey.height || r < 4) return false;
		return true;
	}

	// Detects (upsampling once when nothing is found at the image's own size); best face or none.
	bool detectFace(const Image8& grey, const FaceBox* near, FaceBox& out) {
		for (int up = upsample_; up <= 1; ++up) {
			auto faces = lm_.detect(grey, up);
			lastFaces_ = int(faces.size());
			if (!faces.empty()) {
				if (up > upsample_) upsample_ = up;
				out = faces.front();
				if (near) {
					double best = -1;
					for (const auto& f : faces)
						if (overlap(f, *near) > best) best = overlap(f, *near), out = f;
				}
				return true;
			}
			if (std::max(grey.width, grey.height) > 1600) break;  // large images: faces are big enough
		}
		return false;
	}

	// One frame: fills lm.found/detected/confidence/raw.
	void step(const Image8& grey, FrameLandmarks& f, bool forceDetect) {
		f.found = false;
		Points pts;
		double conf = 0;
		const bool due = !havePrev_ || forceDetect || toSeconds(f.time - lastDetect_) >= o_.redetectSeconds;
		bool ok = false;
		if (havePrev_ && !due) {
			ok = fitChecked(grey, boxFrom(prev_, rel_), pts, conf) && conf >= o_.minConfidence;
		}
		if (!ok) {
			FaceBox box;
			FaceBox prevBox = havePrev_ ? boxFrom(prev_, rel_) : FaceBox{};
			const bool found = detectFace(grey, havePrev_ ? &prevBox : nullptr, box);
			f.faces = lastFaces_;
			if (found) {
				lastDetect_ = f.time;
				// Learn where dlib's box sits on this face, then fit from the box.
				const Points first = lm_.fit(grey, box);
				const BoxRelation r = relationOf(box, first);
				if (!learnt_) rel_ = r, learnt_ = true;
				else rel_ = {0.8 * rel_.left + 0.2 * r.left, 0.8 * rel_.top + 0.2 * r.top, 0.8 * rel_.right + 0.2 * r.right, 0.8 * rel_.bottom + 0.2 * r.bottom};
				ok = fitChecked(grey, box, pts, conf, &first);
				f.detected = ok;
				if (ok && havePrev_ && !due) ok = conf >= 0.5 * o_.minConfidence;
			} else if (havePrev_ && due && !forceDetect) {
				// A scheduled re-detection that misses (profile, blur): keep tracking while fits stay consistent.
				ok = fitChecked(grey, boxFrom(prev_, rel_), pts, conf) && conf >= o_.minConfidence;
			}
		}
		if (!ok) {
			havePrev_ = false;
			return;
		}
		f.found = true;
		f.confidence = conf;
		f.raw = pts;
		prev_ = pts;
		havePrev_ = true;
	}

	void lose() { havePrev_ = false; }

private:
	FaceLandmarker& lm_;
	const TrackOptions& o_;
	BoxRelation rel_;
	bool learnt_ = false;
	bool havePrev_ = false;
	Points prev_;
	Ticks lastDetect_{0};
	int upsample_ = 0;
	int lastFaces_ = 0;
};

// One-euro smoothing over a track segment, in eye distances.
class Smoother {
public:
	explicit Smoother(const SmoothingOptions& o) : o_(o) {}
	Points apply(const Points& raw, Ticks time) {
		if (!o_.enabled) return raw;
		if (!started_) {
			filters_.clear();
			for (Eigen::Index i = 0; i < raw.rows(); ++i)
				for (int c = 0; c < 2; ++c)
					filters_.push_back(i >= 48 && i < 68 ? OneEuroFilter(o_.mouthMinCutoffHz, o_.mouthBeta, o_.derivativeCutoffHz)
					                                     : OneEuroFilter(o_.minCutoffHz, o_.beta, o_.derivativeCutoffHz));
			scale_ = std::max(1.0, eyeDistance(raw));
			started_ = true;
			last_ = time;
		}
		const double dt = std::max(1e-4, toSeconds(time - last_));
		last_ = time;
		Points out(raw.rows(), 2);
		for (Eigen::Index i = 0; i < raw.rows(); ++i)
			for (int c = 0; c < 2; ++c) out(i, c) = filters_[std::size_t(2 * i + c)](raw(i, c) / scale_, dt) * scale_;
		return out;
	}
	void reset() { started_ = false; }

private:
	SmoothingOptions o_;
	std::vector<OneEuroFilter> filters_;
	double scale_ = 1;
	bool started_ = false;
	Ticks last_{0};
};

}  // namespace

std::string defaultDlibModelPath() {
	if (const char* e = std::getenv("TALKHEAD_DLIB_MODEL"); e && *e) return e;
	return "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
}

FaceLandmarker::FaceLandmarker(const std::string& modelPath) {
	std::string error;
	handle_ = dlibModule().open(modelPath, error);
	if (!handle_) throw Error(error);
}

FaceLandmarker::~FaceLandmarker() {
	if (handle_) dlibModule().close(handle_);
}

std::vector<FaceBox> FaceLandmarker::detect(const Image8& grey, int upsample) {
	std::vector<FaceBox> faces;
	std::string error;
	if (!dlibModule().detect(handle_, grey, upsample, faces, error)) throw Error(error);
	return faces;
}

Points FaceLandmarker::fit(const Image8& grey, const FaceBox& box) {
	// Crop the box with a margin and scale it to a fixed width.
	const double s = kCropBoxWidth / std::max(1.0, box.width());
	const double margin = 0.35 * std::max(box.width(), box.height());
	const double x0 = box.left - margin, y0 = box.top - margin;
	const int cw = int(std::lround((box.width() + 2 * margin) * s)), ch = int(std::lround((box.height() + 2 * margin) * s));
	if (cw <= 0 || ch <= 0 || cw > 4096 || ch > 4096) throw Error("face box of absurd size");
	if (crop_.width != cw || crop_.height != ch || crop_.channels != 1) crop_ = Image8(cw, ch, 1);
	// Affine map crop → image: x = x0 + u / s (pixel centres), bilinear, border replicated.
	const cv::Mat src(grey.height, grey.width, CV_8UC1, const_cast<std::uint8_t*>(grey.data.data()));
	cv::Mat dst(ch, cw, CV_8UC1, crop_.data.data());
	const cv::Matx23d m(1 / s, 0, x0, 0, 1 / s, y0);
	cv::warpAffine(src, dst, m, dst.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
	FaceBox inCrop{margin * s, margin * s, (margin + box.width()) * s, (margin + box.height()) * s, 0};
	std::vector<float> xy;
	std::string error;
	if (!dlibModule().fit(handle_, crop_, inCrop, xy, error)) throw Error(error);
	Points p(kIbugPoints, 2);
	for (int i = 0; i < kIbugPoints; ++i) {
		p(i, 0) = x0 + xy[std::size_t(2 * i)] / s;
		p(i, 1) = y0 + xy[std::size_t(2 * i + 1)] / s;
	}
	return p;
}

Image8 toGrey(const Image8& rgb) {
	if (rgb.channels == 1) return rgb;
	Image8 g(rgb.width, rgb.height, 1);
	const std::uint8_t* s = rgb.data.data();
	for (std::size_t i = 0, n = rgb.pixelCount(); i < n; ++i, s += rgb.channels)
		g.data[i] = std::uint8_t((77 * s[0] + 150 * s[1] + 29 * s[2] + 128) >> 8);
	return g;
}

double OneEuroFilter::operator()(double x, double dt) {
	auto alpha = [dt](double cutoff) {
		const double tau = 1.0 / (2 * M_PI * cutoff);
		return 1.0 / (1.0 + tau / dt);
	};
	if (!started_) {
		started_ = true;
		x_ = x;
		dx_ = 0;
		return x;
	}
	const double dx = (x - x_) / dt;
	dx_ += alpha(dCutoff_) * (dx - dx_);
	const double cutoff = minCutoff_ + beta_ * std::abs(dx_);
	x_ += alpha(cutoff) * (x - x_);
	return x_;
}

std::size_t LandmarkTrack::foundCount() const {
	return std::size_t(std::count_if(frames.begin(), frames.end(), [](const FrameLandmarks& f) { return f.found; }));
}

double eyeDistance(const Points& p) {
	if (p.rows() < kIbugPoints) return 0;
	return std::hypot(p(45, 0) - p(36, 0), p(45, 1) - p(36, 1));
}

LandmarkTrack trackVideo(const std::string& path, const TrackOptions& o, ProgressSink& progress, const FrameCallback& onFrame) {
	VideoReader reader(path);
	LandmarkTrack track;
	track.source = path;
	track.info = reader.info();
	std::optional<FaceLandmarker> own;
	FaceLandmarker& lm = o.landmarker ? *o.landmarker : own.emplace(o.modelPath);
	Tracker tracker(lm, o);
	Smoother smoother(o.smoothing);
	Image8 rgb, grey;
	Ticks t{0};
	std::int64_t index = 0, kept = 0;
	const Ticks end = o.duration.count() >= 0 ? o.start + o.duration : Ticks::max();
	const double total = toSeconds(std::min(end, reader.info().duration > Ticks(0) ? reader.info().duration : end) - o.start);
	// Frames between kept ones are skipped without tracking; a gap longer than a few frames re-detects.
	const int every = std::max(1, o.every);
	while (reader.read(rgb, t, index)) {
		if (t < o.start) continue;
		if (t >= end) break;
		if ((kept++) % every != 0) continue;
		FrameLandmarks f;
		f.frame = index;
		f.time = t;
		grey = toGrey(rgb);
		tracker.step(grey, f, false);
		if (f.found) f.points = smoother.apply(f.raw, t);
		else smoother.reset();
		track.frames.push_back(f);
		if (onFrame) onFrame(track.frames.back(), rgb);
		if (total > 0) progress.report(std::min(1.0, toSeconds(t - o.start) / total), "tracking");
	}
	if (track.frames.empty()) throw Error(path, 0, "no video frames" + std::string(o.start.count() > 0 ? " after {{start}}" : ""));
	if (track.foundCount() == 0) throw Error(path, 0, "no face found in any of " + std::to_string(track.frames.size()) + " frames");
	return track;
}

LandmarkTrack landmarkImages(const std::string& path, const TrackOptions& o, ProgressSink& progress, const FrameCallback& onFrame) {
	std::vector<fs::path> files;
	if (fs::is_directory(path)) {
		for (const auto& e : fs::directory_iterator(path))
			if (e.is_regular_file() && isImageFile(e.path())) files.push_back(e.path());
		std::sort(files.begin(), files.end());
		if (files.empty()) throw Error(path, 0, "no images in the folder (.jpg .png .bmp .tif)");
	} else {
		files.push_back(path);
	}
	LandmarkTrack track;
	track.source = path;
	FaceLandmarker lm(o.modelPath);
	for (std::size_t i = 0; i < files.size(); ++i) {
		const Image8 rgb = readImage(files[i].string());
		if (i == 0) track.info.width = rgb.width, track.info.height = rgb.height;
		FrameLandmarks f;
		f.frame = std::int64_t(i);
		f.name = files[i].filename().string();
		Tracker tracker(lm, o);  // every image on its own
		tracker.step(toGrey(rgb), f, true);
		if (f.found) f.points = f.raw;
		track.frames.push_back(f);
		if (onFrame) onFrame(track.frames.back(), rgb);
		progress.report(double(i + 1) / double(files.size()), "landmarks");
	}
	if (track.foundCount() == 0) throw Error(path, 0, "no face found in any of " + std::to_string(files.size()) + " images");
	return track;
}

LandmarkTrack landmarkInput(const std::string& path, const TrackOptions& o, ProgressSink& progress, const FrameCallback& onFrame) {
	if (!fs::exists(path)) throw Error(path, 0, "not found");
	if (fs::is_directory(path) || isImageFile(path)) return landmarkImages(path, o, progress, onFrame);
	return trackVideo(path, o, progress, onFrame);
}

std::string ptsText(const Points& p) {
	std::string s = "version: 1\nn_points: " + std::to_string(p.rows()) + "\n{\n";
	char buf[64];
	for (Eigen::Index i = 0; i < p.rows(); ++i) {
		// iBUG coordinates are 1-based (readPts subtracts 1).
		std::snprintf(buf, sizeof buf, "%.3f %.3f\n", p(i, 0) + 1.0, p(i, 1) + 1.0);
		s += buf;
	}
	return s + "}\n";
}

void writePts(const std::string& path, const Points& p) { writeFileAtomically(path, ptsText(p)); }

namespace {

// The 68 iBUG points' names (models/schemes/ibug-68.scheme: JAW0 … IM7), the columns of a landmarks.tsv.
const std::vector<std::string>& iBugNames() {
	static const std::vector<std::string> names = [] {
		std::vector<std::string> n = loadScheme("ibug-68").pointNames;
		if (n.size() != std::size_t(kIbugPoints)) throw Error("the ibug-68 scheme has " + std::to_string(n.size()) + " points, not 68");
		return n;
	}();
	return names;
}

}  // namespace

std::string landmarksTsv(const LandmarkTrack& track) {
	std::string out = landmarksTsvHeader(iBugNames());
	for (const auto& f : track.frames) {
		LandmarkRow r;
		r.frame = f.frame, r.time = f.time, r.status = f.found ? (f.detected ? "detected" : "tracked") : "lost", r.confidence = f.confidence;
		if (f.found) r.points = f.points;
		appendLandmarksTsvRow(out, r, std::size_t(kIbugPoints));
	}
	return out;
}

LandmarkTrack readLandmarksTsv(const std::string& path) {
	const LandmarksTable t = parseLandmarksTsv(readTextFile(path), path);
	// The 68 iBUG points, by number (the older dialect) or by their scheme names, in any column order.
	std::vector<Eigen::Index> column(std::size_t(kIbugPoints), -1);
	for (std::size_t i = 0; i < t.pointNames.size(); ++i) {
		for (int k = 0; k < kIbugPoints; ++k)
			if (t.iBugIndices ? t.pointNames[i] == std::to_string(k) : t.pointNames[i] == iBugNames()[std::size_t(k)]) column[std::size_t(k)] = Eigen::Index(i);
	}
	for (int k = 0; k < kIbugPoints; ++k)
		if (column[std::size_t(k)] < 0)
			throw Error(path, 1, "has no column for the iBUG point " + iBugNames()[std::size_t(k)] + " (" + std::to_string(t.pointNames.size()) +
			                         " points): a face is tracked by the 68 iBUG points ('corpus landmarks', or a render of an ibug-68 face)");
	LandmarkTrack track;
	track.source = path;
	for (const LandmarkRow& r : t.rows) {
		FrameLandmarks f;
		f.frame = r.frame, f.time = r.time, f.found = r.status != "lost", f.detected = r.status == "detected", f.confidence = r.confidence;
		if (f.found) {
			f.points.resize(kIbugPoints, 2);
			for (int k = 0; k < kIbugPoints; ++k) f.points.row(k) = r.points.row(column[std::size_t(k)]);
			f.raw = f.points;
		}
		track.frames.push_back(std::move(f));
	}
	return track;
}

double rigidJitter(const LandmarkTrack& track, bool raw) {
	static const int rigid[] = {36, 39, 42, 45, 27, 28, 29, 30, 31, 33, 35};
	double sum = 0;
	long count = 0;
	for (std::size_t i = 1; i + 1 < track.frames.size(); ++i) {
		const auto &a = track.frames[i - 1], &b = track.frames[i], &c = track.frames[i + 1];
		if (!a.found || !b.found || !c.found) continue;
		const Points &pa = raw ? a.raw : a.points, &pb = raw ? b.raw : b.points, &pc = raw ? c.raw : c.points;
		const double iod = eyeDistance(pb);
		for (int k : rigid) sum += std::hypot(pa(k, 0) - 2 * pb(k, 0) + pc(k, 0), pa(k, 1) - 2 * pb(k, 1) + pc(k, 1)) / iod, ++count;
	}
	return count ? sum / double(count) : std::numeric_limits<double>::quiet_NaN();
}

std::vector<double> innerLipOpening(const LandmarkTrack& track, bool raw) {
	std::vector<double> v;
	v.reserve(track.frames.size());
	for (const auto& f : track.frames) {
		if (!f.found) {
			v.push_back(std::numeric_limits<double>::quiet_NaN());
			continue;
		}
		v.push_back(mouthMeasures(raw ? f.raw : f.points).opening);
	}
	return v;
}

void drawLandmarks(Image8& rgb, const Points& p, bool ok) {
	cv::Mat m(rgb.height, rgb.width, CV_8UC3, rgb.data.data());
	const double scale = std::max(1.0, eyeDistance(p) / 60);
	const cv::Scalar line = ok ? cv::Scalar(40, 220, 40) : cv::Scalar(230, 140, 0), dot(255, 60, 60);
	auto poly = [&](int a, int b, bool closed) {
		std::vector<cv::Point> v;
		for (int i = a; i <= b; ++i) v.emplace_back(int(std::lround(p(i, 0) * 16)), int(std::lround(p(i, 1) * 16)));
		cv::polylines(m, v, closed, line, 1, cv::LINE_AA, 4);
	};
	if (p.rows() == kIbugPoints) {
		poly(0, 16, false), poly(17, 21, false), poly(22, 26, false), poly(27, 30, false), poly(31, 35, false);
		poly(36, 41, true), poly(42, 47, true), poly(48, 59, true), poly(60, 67, true);
	}
	for (Eigen::Index i = 0; i < p.rows(); ++i)
		cv::circle(m, cv::Point(int(std::lround(p(i, 0) * 16)), int(std::lround(p(i, 1) * 16))), int(std::lround(1.2 * scale * 16)), dot, cv::FILLED, cv::LINE_AA, 4);
}

Image8 contactSheet(const std::vector<Thumbnail>& thumbs, int columns, int cellWidth) {
	if (thumbs.empty()) return Image8(cellWidth, cellWidth, 3, 40);
	const int cols = std::max(1, std::min(columns, int(thumbs.size())));
	const int rows = (int(thumbs.size()) + cols - 1) / cols;
	const double aspect = double(thumbs[0].image.height) / std::max(1, thumbs[0].image.width);
	const int cellH = int(std::lround(cellWidth * aspect)), labelH = 18;
	Image8 sheet(cols * cellWidth, rows * (cellH + labelH), 3, 30);
	cv::Mat sm(sheet.height, sheet.width, CV_8UC3, sheet.data.data());
	for (std::size_t i = 0; i < thumbs.size(); ++i) {
		Image8 img = thumbs[i].image;
		const auto& f = thumbs[i].landmarks;
		if (f.found) drawLandmarks(img, f.points, f.confidence >= 0.5);
		cv::Mat src(img.height, img.width, CV_8UC3, img.data.data()), cell;
		cv::resize(src, cell, cv::Size(cellWidth, cellH), 0, 0, cv::INTER_AREA);
		const int x = int(i % std::size_t(cols)) * cellWidth, y = int(i / std::size_t(cols)) * (cellH + labelH);
		cell.copyTo(sm(cv::Rect(x, y, cellWidth, cellH)));
		char label[96];
		if (!f.name.empty()) std::snprintf(label, sizeof label, "%s%s", f.name.substr(0, 24).c_str(), f.found ? "" : " LOST");
		else std::snprintf(label, sizeof label, "#%lld %.2fs %s", (long long)f.frame, toSeconds(f.time), f.found ? (f.detected ? "det" : "trk") : "LOST");
		if (f.found) std::snprintf(label + std::strlen(label), sizeof label - std::strlen(label), " c%.2f", f.confidence);
		cv::putText(sm, label, cv::Point(x + 4, y + cellH + 13), cv::FONT_HERSHEY_SIMPLEX, 0.4, f.found ? cv::Scalar(220, 220, 220) : cv::Scalar(255, 80, 80), 1, cv::LINE_AA);
		if (!f.found) cv::line(sm, cv::Point(x, y), cv::Point(x + cellWidth - 1, y + cellH - 1), cv::Scalar(255, 60, 60), 2);
	}
	return sheet;
}

const Points& unsmoothedPoints(const FrameLandmarks& f) { return f.raw.rows() == f.points.rows() && f.raw.rows() > 0 ? f.raw : f.points; }

}  // namespace talkhead
