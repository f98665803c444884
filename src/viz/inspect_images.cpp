// SPDX-License-Identifier: GPL-3.0-or-later
#include "viz/inspect_images.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "image/region_mask.h"

namespace talkhead {

namespace {

cv::Mat asMat(Image8& img) { return cv::Mat(img.height, img.width, CV_8UC3, img.data.data()); }

Image8 fromMat(const cv::Mat& m) {
	Image8 out(m.cols, m.rows, 3);
	cv::Mat dst(m.rows, m.cols, CV_8UC3, out.data.data());
	m.copyTo(dst);
	return out;
}

cv::Point2f pt(const Points& p, Eigen::Index i) { return {float(p(i, 0)), float(p(i, 1))}; }

// Face crop: the mean shape's bounding box grown by 15 %, clipped to the frame.
cv::Rect faceBox(const FaceModel& m) {
	double x0 = m.meanShape.col(0).minCoeff(), x1 = m.meanShape.col(0).maxCoeff();
	double y0 = m.meanShape.col(1).minCoeff(), y1 = m.meanShape.col(1).maxCoeff();
	double mx = 0.15 * (x1 - x0), my = 0.15 * (y1 - y0);
	cv::Rect r(int(x0 - mx), int(y0 - my), int(x1 - x0 + 2 * mx), int(y1 - y0 + 2 * my));
	return r & cv::Rect(0, 0, m.width, m.height);
}

cv::Mat cropScaled(Image8& img, const cv::Rect& box, int width) {
	cv::Mat crop = asMat(img)(box), out;
	int height = std::max(1, int(std::lround(double(box.height) * width / box.width)));
	cv::resize(crop, out, cv::Size(width, height), 0, 0, cv::INTER_AREA);
	return out;
}

void label(cv::Mat& m, const std::string& text, cv::Point at, double scale = 0.45) {
	cv::putText(m, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
	cv::putText(m, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

std::vector<Eigen::VectorXf> zeroCoefficients(const FaceModel& m) {
	std::vector<Eigen::VectorXf> c;
	for (const auto& r : m.regions) c.push_back(Eigen::VectorXf::Zero(r.pca.components()));
	return c;
}

}  // namespace

Image8 drawBasefaceMesh(const FaceModel& model) {
	Image8 img = model.baseface;
	cv::Mat m = asMat(img);
	Points framePts = withFrameBorder(model.meanShape, model.width, model.height);
	for (const auto& t : model.frameMesh.triangles)
		for (int e = 0; e < 3; ++e) cv::line(m, pt(framePts, t[e]), pt(framePts, t[(e + 1) % 3]), cv::Scalar(150, 150, 150), 1, cv::LINE_AA);
	for (const auto& t : model.faceMesh.triangles)
		for (int e = 0; e < 3; ++e) cv::line(m, pt(model.meanShape, t[e]), pt(model.meanShape, t[(e + 1) % 3]), cv::Scalar(40, 220, 60), 1, cv::LINE_AA);
	const cv::Scalar regionColors[] = {cv::Scalar(255, 200, 0), cv::Scalar(255, 80, 200), cv::Scalar(0, 200, 255)};
	for (std::size_t r = 0; r < model.scheme.regions.size(); ++r) {
		const auto& spec = model.scheme.regions[r];
		Points b = regionBoundary(spec, model.meanShape);
		Points c = closedCatmullRom(b);
		Eigen::RowVector2d centre = b.colwise().mean();
		std::vector<cv::Point> poly;
		for (Eigen::Index i = 0; i < c.rows(); ++i) {
			Eigen::RowVector2d q = (c.row(i) - centre) * (1 + spec.grow) + centre;
			poly.emplace_back(int(std::lround(q(0))), int(std::lround(q(1))));
		}
		cv::polylines(m, poly, true, regionColors[r % 3], 2, cv::LINE_AA);
	}
	for (Eigen::Index i = 0; i < model.meanShape.rows(); ++i) cv::circle(m, pt(model.meanShape, i), 3, cv::Scalar(255, 40, 40), -1, cv::LINE_AA);
	label(m, "baseface (sample " + std::to_string(model.basefaceIndex) + "): frame mesh grey, face mesh green, regions", {10, 24}, 0.6);
	return img;
}

Image8 drawRegionModes(const FaceModel& model, int region, int modes) {
	const RegionModel& r = model.regions.at(region);
	modes = int(std::min<Eigen::Index>(modes, r.pca.components()));
	const cv::Rect box = faceBox(model);
	const int cell = 260;
	std::vector<cv::Mat> rows;
	for (int i = 0; i < modes; ++i) {
		std::vector<cv::Mat> cells;
		const double sd = std::sqrt(r.pca.eigenvalues(i));
		for (int k = -1; k <= 1; ++k) {
			auto coeffs = zeroCoefficients(model);
			coeffs[region](i) = float(2.0 * k * sd);
			Image appearance = compositeAppearance(model, coeffs);
			Points shape = synthesizeShape(model, coeffs[region], region);
			Image8 frame = warpFromMean(model, appearance, shape);
			cv::Mat c = cropScaled(frame, box, cell);
			label(c, "mode " + std::to_string(i + 1) + (k < 0 ? "  -2sd" : k > 0 ? "  +2sd" : "  mean"), {6, 18});
			cells.push_back(c);
		}
		cv::Mat row;
		cv::hconcat(cells, row);
		rows.push_back(row);
	}
	cv::Mat sheet;
	cv::vconcat(rows, sheet);
	cv::Mat header(28, sheet.cols, CV_8UC3, cv::Scalar(40, 40, 40));
	label(header, "region '" + r.name + "': first modes at -2 / 0 / +2 standard deviations", {8, 19}, 0.5);
	cv::vconcat(header, sheet, sheet);
	return fromMat(sheet);
}

Image8 drawVarianceCurves(const FaceModel& model) {
	const int W = 900, H = 560, left = 70, right = 30, top = 40, bottom = 60;
	cv::Mat m(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
	Eigen::Index maxK = 1;
	for (const auto& r : model.regions) maxK = std::max(maxK, r.pca.eigenvalues.size());
	auto X = [&](double k) { return int(left + (W - left - right) * k / double(maxK)); };
	auto Y = [&](double v) { return int(H - bottom - (H - top - bottom) * v); };
	for (int p = 0; p <= 10; ++p) {
		cv::line(m, {X(0), Y(p / 10.0)}, {X(double(maxK)), Y(p / 10.0)}, cv::Scalar(230, 230, 230));
		cv::putText(m, std::to_string(p * 10) + "%", {8, Y(p / 10.0) + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
	}
	cv::line(m, {X(0), Y(0)}, {X(double(maxK)), Y(0)}, cv::Scalar(0, 0, 0));
	cv::line(m, {X(0), Y(0)}, {X(0), Y(1)}, cv::Scalar(0, 0, 0));
	cv::putText(m, "number of principal components (of " + std::to_string(maxK) + ")", {W / 2 - 150, H - 20},
	            cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
	cv::putText(m, "cumulative explained variance per region", {left, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
	const cv::Scalar colors[] = {cv::Scalar(200, 60, 30), cv::Scalar(40, 150, 40), cv::Scalar(30, 60, 220)};
	for (std::size_t ri = 0; ri < model.regions.size(); ++ri) {
		const auto& pca = model.regions[ri].pca;
		const cv::Scalar col = colors[ri % 3];
		std::vector<cv::Point> curve{{X(0), Y(0)}};
		double acc = 0, total = pca.eigenvalues.sum();
		for (Eigen::Index k = 0; k < pca.eigenvalues.size(); ++k) {
			acc += pca.eigenvalues(k);
			curve.emplace_back(X(double(k + 1)), Y(acc / total));
		}
		cv::polylines(m, curve, false, col, 2, cv::LINE_AA);
		std::string legend = model.regions[ri].name;
		for (double f : {0.8, 0.9}) {
			Eigen::Index k = pca.componentsFor(f);
			cv::circle(m, {X(double(k)), Y(f)}, 5, col, -1, cv::LINE_AA);
			legend += "  " + std::to_string(int(f * 100)) + "%: " + std::to_string(k) + " PCs";
		}
		cv::putText(m, legend, {W - 420, H - bottom - 20 - 22 * int(model.regions.size() - ri)}, cv::FONT_HERSHEY_SIMPLEX, 0.5, col, 1, cv::LINE_AA);
	}
	return fromMat(m);
}

Image8 drawContactSheet(const FaceModel& model, int thumbWidth, const std::function<std::string(const SampleInfo&)>& labelOf) {
	const cv::Rect box = faceBox(model);
	const std::size_t n = model.sampleCount();
	const int cols = int(std::min<std::size_t>(n, std::max<std::size_t>(1, std::size_t(std::ceil(std::sqrt(double(n) * 1.6))))));
	const int rowsN = int((n + cols - 1) / cols);
	const int thumbH = std::max(1, int(std::lround(double(box.height) * thumbWidth / box.width)));
	cv::Mat sheet(rowsN * thumbH, cols * thumbWidth, CV_8UC3, cv::Scalar(30, 30, 30));
	const std::size_t chunk = 196;  // appearances by GEMM, a chunk of samples at a time (packing the basis once per chunk)
	for (std::size_t first = 0; first < n; first += chunk) {
		const std::size_t count = std::min(chunk, n - first);
		std::vector<Eigen::MatrixXf> appearances;
		for (const auto& r : model.regions)
			appearances.push_back(synthesizeAppearances(r, r.pca.trainingCoefficients.middleRows(Eigen::Index(first), Eigen::Index(count)).transpose()));
		parallelFor(count, 0, [&](std::size_t k) {
			const std::size_t i = first + k;
			std::vector<Eigen::VectorXf> a;
			for (const auto& m : appearances) a.push_back(m.col(Eigen::Index(k)));
			Image8 frame = warpFromMean(model, compositeRegions(model, a), model.alignedShapes[i]);
			cv::Mat t = cropScaled(frame, box, thumbWidth);
			const auto& s = model.samples[i];
			label(t, labelOf ? labelOf(s) : (s.emotion == "-" ? std::string() : s.emotion + " ") + s.cdv, {4, thumbH - 6}, 0.4);
			t.copyTo(sheet(cv::Rect(int(i % cols) * thumbWidth, int(i / cols) * thumbH, thumbWidth, thumbH)));
		});
	}
	return fromMat(sheet);
}

}  // namespace talkhead
