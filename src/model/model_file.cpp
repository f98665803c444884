// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/model_file.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <fstream>
#include <sys/mman.h>
#include <unistd.h>

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/interrupt.h"
#include "base/memory.h"

namespace talkhead {

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE types expected");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the .thm writer assumes a little-endian host"
#endif

namespace {
constexpr std::uint64_t kPrime = 0x100000001B3ull * 0x9E3779B1ull | 1ull;
inline std::uint64_t mix(std::uint64_t h, std::uint64_t w) {
	h = (h ^ w) * kPrime;
	return h ^ (h >> 31);
}
}  // namespace

// Streaming checksum: four independent multiply–xor lanes over interleaved 8-byte words (so the CPU
// overlaps them: several GB/s), combined with the length at finish().
class Checksum64 {
public:
	explicit Checksum64(std::uint64_t seed = 0x9E3779B97F4A7C15ull) {
		for (int i = 0; i < 4; ++i) h_[i] = seed + std::uint64_t(i) * 0xD6E8FEB86659FD93ull;
	}
	void update(const void* data, std::size_t n) {
		const auto* p = static_cast<const unsigned char*>(data);
		size_ += n;
		while (n && pending_) {
			tail_[pending_++] = *p++;
			--n;
			if (pending_ == 32) {
				block(tail_);
				pending_ = 0;
			}
		}
		for (; n >= 32; n -= 32, p += 32) block(p);
		while (n--) tail_[pending_++] = *p++;
	}
	std::uint64_t finish() const {
		std::uint64_t h = h_[0];
		for (int i = 1; i < 4; ++i) h = mix(h, h_[i]);
		for (std::size_t i = 0; i < pending_; ++i) h = mix(h, tail_[i]);
		return mix(h, size_);
	}

private:
	void block(const unsigned char* p) {
		std::uint64_t w[4];
		std::memcpy(w, p, 32);
		for (int i = 0; i < 4; ++i) h_[i] = mix(h_[i], w[i]);
	}
	std::uint64_t h_[4];
	std::uint64_t size_ = 0;
	unsigned char tail_[32] = {};
	std::size_t pending_ = 0;
};

std::uint64_t checksum64(const void* data, std::size_t size, std::uint64_t seed) {
	Checksum64 c(seed);
	c.update(data, size);
	return c.finish();
}

namespace {

constexpr char kMagic[8] = {'T', 'A', 'L', 'K', 'H', 'E', 'A', 'D'};
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8 + 8;
enum class Type : std::uint32_t { F32 = 1, F64 = 2, I32 = 3, U8 = 4, Str = 5, U64 = 6 };

// Large arrays are read straight into their final storage, with huge pages asked for first.

// Streams records to a file, hashing as it goes; the header's size and checksum are patched at the end.
class Writer {
public:
	Writer(std::FILE* f) : f_(f) {}
	void raw(const void* p, std::size_t n) {
		if (n && std::fwrite(p, 1, n, f_) != n && ok_) {
			ok_ = false;
			errno_ = errno;
		}
		sum_.update(p, n);
		record_.update(p, n);
		size_ += n;
	}
	template <class T>
	void pod(T v) {
		raw(&v, sizeof v);
	}
	// Each record ends with the checksum of its own bytes, so a reader may skip records it does not need
	// (render skips the bases) and still verify everything it reads.
	void endRecord() {
		const std::uint64_t c = record_.finish();
		raw(&c, 8);
	}
	void header(const std::string& name, Type t, std::uint64_t count) {
		record_ = Checksum64();
		pod<std::uint32_t>(std::uint32_t(name.size()));
		raw(name.data(), name.size());
		pod<std::uint32_t>(std::uint32_t(t));
		pod<std::uint64_t>(count);
	}
	void f32(const std::string& name, const float* p, std::size_t n) {
		header(name, Type::F32, n);
		raw(p, n * 4);
		endRecord();
	}
	void f64(const std::string& name, const double* p, std::size_t n) {
		header(name, Type::F64, n);
		raw(p, n * 8);
		endRecord();
	}
	void i32(const std::string& name, const std::int32_t* p, std::size_t n) {
		header(name, Type::I32, n);
		raw(p, n * 4);
		endRecord();
	}
	void u8(const std::string& name, const std::uint8_t* p, std::size_t n) {
		header(name, Type::U8, n);
		raw(p, n);
		endRecord();
	}
	void u64(const std::string& name, const std::uint64_t* p, std::size_t n) {
		header(name, Type::U64, n);
		raw(p, n * 8);
		endRecord();
	}
	void i64(const std::string& name, std::int64_t v) {
		double d = double(v);
		f64(name, &d, 1);
	}
	void strings(const std::string& name, const std::vector<std::string>& v) {
		header(name, Type::Str, v.size());
		for (const auto& s : v) {
			pod<std::uint32_t>(std::uint32_t(s.size()));
			raw(s.data(), s.size());
		}
		endRecord();
	}
	bool ok() const { return ok_; }
	int error() const { return errno_; }  // errno of the first failed write
	std::uint64_t size() const { return size_; }
	std::uint64_t checksum() const { return sum_.finish(); }

private:
	std::FILE* f_;
	Checksum64 sum_, record_;
	std::uint64_t size_ = 0;
	bool ok_ = true;
	int errno_ = 0;
};

// Reads records from the payload, hashing as it goes. Sizes are checked against the bytes left before
// anything is allocated, so a corrupt count cannot ask for more memory than the file holds.
class Reader {
public:
	Reader(std::FILE* f, std::uint64_t size, std::string path) : f_(f), size_(size), left_(size), path_(std::move(path)) {}
	// File offset of the next byte to be read.
	std::uint64_t position() const { return kHeaderSize + size_ - left_; }
	const std::string& path() const { return path_; }
	void raw(void* p, std::size_t n) {
		need(n);
		if (n && std::fread(p, 1, n, f_) != n) fail("unexpected end of data");
		sum_.update(p, n);
		record_.update(p, n);
		left_ -= n;
	}
	template <class T>
	T pod() {
		T v;
		raw(&v, sizeof v);
		return v;
	}
	std::size_t expect(const std::string& name, Type t, std::size_t elemSize) {
		record_ = Checksum64();
		recordName_ = name;
		std::uint32_t len = pod<std::uint32_t>();
		need(len);
		std::string got(len, '\0');
		raw(got.data(), len);
		if (got != name) fail("expected record '" + name + "', found '" + got.substr(0, 40) + "'");
		if (pod<std::uint32_t>() != std::uint32_t(t)) fail("record '" + name + "' has the wrong type");
		std::uint64_t count = pod<std::uint64_t>();
		if (elemSize && count > left_ / elemSize) fail("record '" + name + "' runs past the end of the file");
		return std::size_t(count);
	}
	// Reads an array record straight into storage that `alloc(count)` returns.
	template <class T, class Alloc>
	void arrayInto(const std::string& name, Type t, Alloc&& alloc) {
		std::size_t n = expect(name, t, sizeof(T));
		T* dst = alloc(n);
		adviseHugePages(dst, n * sizeof(T));
		raw(dst, n * sizeof(T));
		endRecord();
	}
	// Skips an array record without reading its data (its checksum cannot be verified then).
	void skip(const std::string& name, Type t, std::size_t elemSize) {
		skipData(expect(name, t, elemSize) * elemSize + 8);
	}
	// Skips n bytes of the current record (its checksum cannot be verified then).
	void skipData(std::size_t n) {
		need(n);
		if (std::fseek(f_, long(n), SEEK_CUR) != 0) fail("cannot seek");
		left_ -= n;
		skipped_ = true;
	}
	bool skipped() const { return skipped_; }
	// Reads n bytes of the current record only to hash them (its checksum stays verifiable).
	void readThrough(std::size_t n) {
		std::vector<char> buf(std::min<std::size_t>(n, 1 << 20));
		while (n > 0) {
			const std::size_t c = std::min(n, buf.size());
			raw(buf.data(), c);
			n -= c;
		}
	}
	template <class T>
	std::vector<T> array(const std::string& name, Type t) {
		std::vector<T> v;
		arrayInto<T>(name, t, [&](std::size_t n) {
			resizePrefaulted(v, n);
			return v.data();
		});
		return v;
	}
	std::vector<float> f32(const std::string& name) { return array<float>(name, Type::F32); }
	std::vector<double> f64(const std::string& name) { return array<double>(name, Type::F64); }
	std::vector<std::int32_t> i32(const std::string& name) { return array<std::int32_t>(name, Type::I32); }
	std::vector<std::uint8_t> u8(const std::string& name) { return array<std::uint8_t>(name, Type::U8); }
	std::vector<std::uint64_t> u64(const std::string& name) { return array<std::uint64_t>(name, Type::U64); }
	double scalar(const std::string& name) {
		auto v = f64(name);
		if (v.size() != 1) fail("record '" + name + "' should hold one value");
		return v[0];
	}
	std::vector<std::string> strings(const std::string& name) {
		std::size_t n = expect(name, Type::Str, 4);
		std::vector<std::string> v;
		v.reserve(n);
		for (std::size_t i = 0; i < n; ++i) {
			std::uint32_t len = pod<std::uint32_t>();
			need(len);
			std::string s(len, '\0');
			raw(s.data(), len);
			v.push_back(std::move(s));
		}
		endRecord();
		return v;
	}
	void endRecord() {
		const std::uint64_t expected = record_.finish();
		std::uint64_t stored;
		raw(&stored, 8);
		if (stored != expected) fail("checksum mismatch in record '" + recordName_ + "'");
	}
	[[noreturn]] void fail(const std::string& what) const { throw Error(path_, 0, "corrupt model file: " + what); }
	void need(std::size_t n) const {
		if (n > left_) fail("unexpected end of data");
	}
	bool atEnd() const { return left_ == 0; }
	std::uint64_t checksum() const { return sum_.finish(); }

private:
	std::FILE* f_;
	std::uint64_t size_, left_;
	std::string path_;
	Checksum64 sum_, record_;
	std::string recordName_;
	bool skipped_ = false;
};

// The appearance cache of one region left in the model file: pread one sample at a time and verify it
// against its own checksum.
class FileAppearanceSource : public AppearanceSource {
public:
	FileAppearanceSource(std::shared_ptr<int> fd, std::string path, std::uint64_t offset, std::size_t sampleSize, std::vector<std::uint64_t> sums,
	                     std::string region)
	    : fd_(std::move(fd)), path_(std::move(path)), offset_(offset), size_(sampleSize), sums_(std::move(sums)), region_(std::move(region)) {}
	void read(std::size_t sample, std::uint8_t* out) const override {
		if (sample >= sums_.size()) throw std::out_of_range("appearance sample out of range");
		std::size_t done = 0;
		const std::uint64_t at = offset_ + std::uint64_t(sample) * size_;
		while (done < size_) {
			const ssize_t n = ::pread(*fd_, out + done, size_ - done, off_t(at + done));
			if (n <= 0) throw Error(path_, 0, "cannot read the model's appearance cache" + std::string(n < 0 ? std::string(": ") + std::strerror(errno) : ""));
			done += std::size_t(n);
		}
		if (checksum64(out, size_) != sums_[sample])
			throw Error(path_, 0, "corrupt model file: checksum mismatch in the cached appearance of sample " + std::to_string(sample) + " (region " +
			                          region_ + ")");
	}

private:
	std::shared_ptr<int> fd_;
	std::string path_;
	std::uint64_t offset_;
	std::size_t size_;
	std::vector<std::uint64_t> sums_;
	std::string region_;
};

// A region's keypose appearances from its first k components (ComponentLevels): ā + σ ∘ (D_a α), 8-bit
// with the same rounding as the build's cache.
class ReducedAppearanceSource : public AppearanceSource {
public:
	// basis: n × k or wider (its first k columns and q3 rows are used); coefficients: samples × ≥ k.
	ReducedAppearanceSource(Eigen::VectorXf mean, Eigen::VectorXf sigma, Eigen::MatrixXf basis, Eigen::MatrixXf coefficients, Eigen::Index q3, Eigen::Index k)
	    : mean_(mean.head(q3)), sigma_(sigma.head(q3)), basis_(std::move(basis)), coefficients_(coefficients.leftCols(k)), q3_(q3), k_(k) {}
	void read(std::size_t sample, std::uint8_t* out) const override {
		if (Eigen::Index(sample) >= coefficients_.rows()) throw std::out_of_range("appearance sample out of range");
		const Eigen::VectorXf a = mean_ + sigma_.cwiseProduct(basis_.topLeftCorner(q3_, k_) * coefficients_.row(Eigen::Index(sample)).transpose());
		quantizeAppearance(a.data(), std::size_t(a.size()), out);
	}

private:
	Eigen::VectorXf mean_, sigma_;
	Eigen::MatrixXf basis_, coefficients_;
	Eigen::Index q3_, k_;
};

void writePoints(Writer& w, const std::string& name, const Points& p) { w.f64(name, p.data(), std::size_t(p.size())); }

Points readPoints(Reader& r, const std::string& name, Eigen::Index k) {
	auto v = r.f64(name);
	if (Eigen::Index(v.size()) != 2 * k) r.fail("record '" + name + "' has the wrong size");
	Points p(k, 2);
	std::memcpy(p.data(), v.data(), v.size() * 8);
	return p;
}

void writeMesh(Writer& w, const std::string& name, const TriangleMesh& m) {
	std::vector<std::int32_t> v;
	v.push_back(m.vertexCount);
	for (const auto& t : m.triangles) v.insert(v.end(), t.begin(), t.end());
	w.i32(name, v.data(), v.size());
}

TriangleMesh readMesh(Reader& r, const std::string& name) {
	auto v = r.i32(name);
	if (v.empty() || (v.size() - 1) % 3) r.fail("record '" + name + "' is not a triangle list");
	TriangleMesh m;
	m.vertexCount = v[0];
	for (std::size_t i = 1; i < v.size(); i += 3) {
		Triangle t{v[i], v[i + 1], v[i + 2]};
		for (int x : t)
			if (x < 0 || x >= m.vertexCount) r.fail("record '" + name + "' has a vertex index out of range");
		m.triangles.push_back(t);
	}
	return m;
}

}  // namespace

namespace {

void writeRecords(Writer& w, const FaceModel& model) {
	const Scheme& s = model.scheme;
	w.strings("scheme.name", {s.name});
	w.strings("scheme.points", s.pointNames);
	w.strings("scheme.classes", s.pointClasses);
	w.f64("scheme.weights", s.weights.data(), std::size_t(s.weights.size()));
	w.i64("scheme.regions", std::int64_t(s.regions.size()));
	for (const auto& r : s.regions) {
		w.strings("region.name", {r.name});
		w.i32("region.boundary", r.boundary.data(), r.boundary.size());
		// Version 5: per boundary entry, the second point (−1: none) and the fraction towards it.
		std::vector<double> towards;
		for (std::size_t i = 0; i < r.boundary.size(); ++i) {
			const bool between = i < r.towards.size() && r.towards[i] >= 0;
			towards.push_back(between ? r.towards[i] : -1);
			towards.push_back(between ? r.fraction[i] : 0);
		}
		w.f64("region.towards", towards.data(), towards.size());
		double gf[2] = {r.grow, r.feather};
		w.f64("region.growFeather", gf, 2);
	}
	w.i64("width", model.width);
	w.i64("height", model.height);
	const Eigen::Index k = model.pointCount();
	w.i64("points", k);
	w.i64("samples", std::int64_t(model.samples.size()));
	writePoints(w, "meanShape", model.meanShape);
	std::vector<double> aligned;
	aligned.reserve(model.alignedShapes.size() * 2 * k);
	for (const auto& a : model.alignedShapes) aligned.insert(aligned.end(), a.data(), a.data() + 2 * k);
	w.f64("alignedShapes", aligned.data(), aligned.size());
	std::vector<std::string> labels;
	for (const auto& smp : model.samples) {
		labels.push_back(smp.image);
		labels.push_back(smp.emotion);
		labels.push_back(smp.cdv);
		labels.push_back(smp.word);
		for (const auto& c : smp.context) labels.push_back(c);
	}
	w.strings("sampleLabels", labels);
	w.i64("referenceIndex", std::int64_t(model.referenceIndex));
	w.i64("procrustesIterations", model.procrustesIterations);
	w.f64("procrustesChange", &model.procrustesChange, 1);
	writeMesh(w, "faceMesh", model.faceMesh);
	writeMesh(w, "frameMesh", model.frameMesh);
	w.i64("basefaceIndex", std::int64_t(model.basefaceIndex));
	w.i64("closedEyesIndex", model.closedEyesIndex);  // version 5
	w.u8("baseface", model.baseface.data.data(), model.baseface.data.size());
	w.i64("regions", std::int64_t(model.regions.size()));
	for (const auto& r : model.regions) {
		const auto& p = r.pca;
		w.strings("name", {r.name});
		w.i32("pixels", r.pixels.data(), r.pixels.size());
		w.f32("alpha", r.alpha.data(), r.alpha.size());
		w.f32("mean", p.mean.data(), std::size_t(p.mean.size()));
		w.f32("sigma", p.sigma.data(), std::size_t(p.sigma.size()));
		w.f64("eigenvalues", p.eigenvalues.data(), std::size_t(p.eigenvalues.size()));
		w.i64("components", p.basis.cols());
		w.f32("basis", p.basis.data(), std::size_t(p.basis.size()));
		w.f32("coefficients", p.trainingCoefficients.data(), std::size_t(p.trainingCoefficients.size()));
		w.u8("appearances", r.sampleAppearances.data(), r.sampleAppearances.size());
		// One checksum per sample's cached appearance, so a render can read just the samples it uses.
		std::vector<std::uint64_t> sums;
		const std::size_t q3 = std::size_t(r.appearanceSize());
		for (std::size_t i = 0; q3 && (i + 1) * q3 <= r.sampleAppearances.size(); ++i)
			sums.push_back(checksum64(&r.sampleAppearances[i * q3], q3));
		w.u64("appearanceChecksums", sums.data(), sums.size());
	}
}

}  // namespace

void saveModel(const FaceModel& model, const std::string& path) {
	namespace fs = std::filesystem;
	fs::path target(path);
	fs::path tmp = temporaryNameFor(path);
	std::FILE* f = std::fopen(tmp.c_str(), "wb");
	if (!f) throw Error(path, 0, std::string("cannot write model: ") + std::strerror(errno));
	char head[kHeaderSize] = {};
	std::memcpy(head, kMagic, 8);
	const std::uint32_t version = kModelFormatVersion;
	std::memcpy(head + 8, &version, 4);
	bool ok = std::fwrite(head, 1, kHeaderSize, f) == kHeaderSize;
	Writer w(f);
	writeRecords(w, model);
	const std::uint64_t size = w.size(), sum = w.checksum();
	int err = w.ok() ? 0 : w.error();
	ok = ok && w.ok() && std::fseek(f, 16, SEEK_SET) == 0 && std::fwrite(&size, 8, 1, f) == 1 && std::fwrite(&sum, 8, 1, f) == 1;
	if (!ok && !err) err = errno;
	errno = 0;
	if (std::fclose(f) != 0) {
		if (ok || !err) err = errno;
		ok = false;
	}
	std::error_code ec;
	if (ok) fs::rename(tmp, target, ec);
	if (!ok || ec) std::remove(tmp.c_str());
	releaseTemporary(tmp.string());
	if (!ok || ec) {
		throw Error(path, 0, "cannot write model: " + (ec ? ec.message() : std::string(std::strerror(err ? err : EIO))));
	}
}

namespace {

FaceModel readRecords(Reader& r, bool bases, std::uint32_t version, const ComponentLevels& levels);

// The checksum of the payload from `offset` to the end, read in chunks (used to tell corruption from
// a format problem when parsing stops early).
std::uint64_t payloadChecksum(std::FILE* f) {
	std::fseek(f, long(kHeaderSize), SEEK_SET);
	Checksum64 c;
	std::vector<char> buf(1 << 20);
	std::size_t n;
	while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) c.update(buf.data(), n);
	return c.finish();
}

}  // namespace

ComponentLevels parseComponentLevels(const std::string& spec) {
	ComponentLevels out;
	if (spec == "all") return out;  // every region at full quality
	auto bad = [&](const std::string& what) -> Error {
		return Error("{{components}} '" + spec.substr(0, 80) + "': " + what + " (expected REGION=N, REGION=P% or REGION=all, comma-separated, e.g. face=20,lips=all)");
	};
	std::size_t at = 0;
	while (at <= spec.size()) {
		std::size_t end = spec.find(',', at);
		if (end == std::string::npos) end = spec.size();
		const std::string item = spec.substr(at, end - at);
		const std::size_t eq = item.find('=');
		if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) throw bad("'" + item.substr(0, 40) + "' is not REGION=LEVEL");
		const std::string region = item.substr(0, eq), value = item.substr(eq + 1);
		if (out.count(region)) throw bad("region '" + region.substr(0, 40) + "' is named twice");
		ComponentLevel level;
		char* e = nullptr;
		if (value == "all") {
			level.evr = 1.0;
		} else if (value.back() == '%') {
			const double p = std::strtod(value.c_str(), &e);
			if (e != value.c_str() + value.size() - 1 || !(p > 0 && p <= 100)) throw bad("'" + value.substr(0, 20) + "' is not a percentage in (0, 100]");
			level.evr = p / 100;
		} else {
			const long n = std::strtol(value.c_str(), &e, 10);
			if (e != value.c_str() + value.size() || n < 1 || n > 10000000 || !std::isdigit(static_cast<unsigned char>(value[0])))
				throw bad("'" + value.substr(0, 20) + "' is not a component count ≥ 1");
			level.count = n;
		}
		out[region] = level;
		at = end + 1;
	}
	return out;
}

FaceModel loadModel(const std::string& path, ModelParts parts, const ComponentLevels& levels) {
	std::FILE* f = std::fopen(path.c_str(), "rb");
	if (!f) throw Error(path, 0, std::string("cannot open model: ") + std::strerror(errno));
	struct Closer {
		std::FILE* f;
		~Closer() { std::fclose(f); }
	} closer{f};
	std::setvbuf(f, nullptr, _IOFBF, 1 << 16);
	char head[kHeaderSize];
	std::size_t got = std::fread(head, 1, kHeaderSize, f);
	if (got != kHeaderSize || std::memcmp(head, kMagic, 8) != 0) throw Error(path, 0, "not a talkhead model file (bad magic)");
	std::uint32_t version;
	std::uint64_t size, sum;
	std::memcpy(&version, head + 8, 4);
	std::memcpy(&size, head + 16, 8);
	std::memcpy(&sum, head + 24, 8);
	if (version != kModelFormatVersion && version != 4)
		throw Error(path, 0, "model format version " + std::to_string(version) + " is not supported (this build reads versions 4 to " +
		                         std::to_string(kModelFormatVersion) + "; rebuild the model with 'talkhead build')");
	std::error_code ec;
	auto fileSize = std::filesystem::file_size(path, ec);
	if (ec || fileSize != kHeaderSize + size)
		throw Error(path, 0, "truncated or padded model file: header says " + std::to_string(kHeaderSize + size) + " bytes, file has " +
		                         std::to_string(ec ? 0 : fileSize));
	Reader r(f, size, path);
	FaceModel m;
	try {
		m = readRecords(r, parts == ModelParts::All, version, levels);
	} catch (const Error& e) {
		// A damaged record says so itself; anything else that stops the parse is reported as damage
		// when the payload's checksum disagrees (a flipped byte in a length field, say).
		if (std::string(e.what()).find("checksum mismatch") == std::string::npos && payloadChecksum(f) != sum)
			throw Error(path, 0, "corrupt model file: checksum mismatch");
		throw;
	}
	if (!r.skipped() && r.checksum() != sum) throw Error(path, 0, "corrupt model file: checksum mismatch");
	return m;
}

namespace {

std::string oneString(Reader& r, const std::string& name) {
	auto v = r.strings(name);
	if (v.size() != 1) r.fail("record '" + name + "' should hold one string");
	return v[0];
}

std::int64_t countOf(Reader& r, const std::string& name, double maxValue) {
	double v = r.scalar(name);
	if (!(v >= 0 && v <= maxValue)) r.fail("record '" + name + "' is out of range");
	return std::int64_t(v);
}

Scheme readSchemeRecords(Reader& r, std::uint32_t version) {
	Scheme s;
	auto one = [&](const std::string& name) { return oneString(r, name); };
	auto count = [&](const std::string& name, double maxValue) { return countOf(r, name, maxValue); };
	s.name = one("scheme.name");
	s.pointNames = r.strings("scheme.points");
	s.pointClasses = r.strings("scheme.classes");
	auto wts = r.f64("scheme.weights");
	const Eigen::Index k = Eigen::Index(s.pointNames.size());
	if (s.pointClasses.size() != s.pointNames.size() || Eigen::Index(wts.size()) != k || k < 3) r.fail("inconsistent scheme");
	s.weights = Eigen::Map<Eigen::VectorXd>(wts.data(), k);
	std::int64_t regionSpecs = count("scheme.regions", 64);
	for (std::int64_t i = 0; i < regionSpecs; ++i) {
		RegionSpec rs;
		rs.name = one("region.name");
		auto b = r.i32("region.boundary");
		for (int x : b)
			if (x < 0 || x >= k) r.fail("region boundary index out of range");
		rs.boundary.assign(b.begin(), b.end());
		if (version >= 5) {  // version 4 has no region.towards: every boundary entry is a point
			auto t = r.f64("region.towards");
			if (t.size() != 2 * b.size()) r.fail("bad region.towards");
			for (std::size_t i = 0; i < b.size(); ++i) {
				const double other = t[2 * i], frac = t[2 * i + 1];
				if (other == -1) {
					rs.towards.push_back(-1);
					rs.fraction.push_back(0);
				} else if (other >= 0 && other < double(k) && other == std::floor(other) && frac >= -3 && frac <= 3) {
					rs.towards.push_back(int(other));
					rs.fraction.push_back(frac);
				} else {
					r.fail("region.towards out of range");
				}
			}
		}
		auto gf = r.f64("region.growFeather");
		if (gf.size() != 2) r.fail("bad region options");
		rs.grow = gf[0];
		rs.feather = gf[1];
		s.regions.push_back(rs);
	}
	completeSchemeParts(s);
	return s;
}

// The frame, the shapes, the samples' labels, the meshes and the baseface.
void readShapeRecords(Reader& r, std::uint32_t version, FaceModel& m) {
	auto count = [&](const std::string& name, double maxValue) { return countOf(r, name, maxValue); };
	const Eigen::Index k = Eigen::Index(m.scheme.pointNames.size());
	m.width = int(count("width", 1e5));
	m.height = int(count("height", 1e5));
	if (count("points", 1e5) != k) r.fail("point count differs from the scheme");
	const std::size_t samples = std::size_t(count("samples", 1e8));
	m.meanShape = readPoints(r, "meanShape", k);
	auto aligned = r.f64("alignedShapes");
	if (aligned.size() != samples * 2 * std::size_t(k)) r.fail("alignedShapes has the wrong size");
	for (std::size_t i = 0; i < samples; ++i) {
		Points p(k, 2);
		std::memcpy(p.data(), aligned.data() + i * 2 * k, 2 * k * 8);
		m.alignedShapes.push_back(p);
	}
	auto labels = r.strings("sampleLabels");
	if (labels.size() != samples * 9) r.fail("sampleLabels has the wrong size");
	for (std::size_t i = 0; i < samples; ++i) {
		SampleInfo si;
		si.image = labels[i * 9];
		si.emotion = labels[i * 9 + 1];
		si.cdv = labels[i * 9 + 2];
		si.word = labels[i * 9 + 3];
		for (int c = 0; c < 5; ++c) si.context[c] = labels[i * 9 + 4 + c];
		m.samples.push_back(si);
	}
	m.referenceIndex = std::size_t(count("referenceIndex", double(samples)));
	m.procrustesIterations = int(count("procrustesIterations", 1e9));
	m.procrustesChange = r.scalar("procrustesChange");
	m.faceMesh = readMesh(r, "faceMesh");
	m.frameMesh = readMesh(r, "frameMesh");
	if (m.faceMesh.vertexCount != k || m.frameMesh.vertexCount != k + kFrameBorderPoints) r.fail("mesh vertex counts differ from the scheme");
	m.basefaceIndex = std::size_t(count("basefaceIndex", double(samples)));
	if (version >= 5) {
		const double closed = r.scalar("closedEyesIndex");
		if (!(closed >= -1 && closed < double(samples)) || closed != std::floor(closed)) r.fail("record 'closedEyesIndex' is out of range");
		m.closedEyesIndex = long(closed);
	}
	auto base = r.u8("baseface");
	if (base.size() != std::size_t(m.width) * m.height * 3) r.fail("baseface has the wrong size");
	m.baseface.width = m.width;  // adopt the buffer (no zero-filled image first)
	m.baseface.height = m.height;
	m.baseface.channels = 3;
	m.baseface.data = std::move(base);
}

// What a region's load does with its PCA: all of it (a full load), only the kept columns (a render with
// --components), or none (a render: the appearance cache serves).
struct RegionLoad {
	bool bases;   // a full load
	bool reduce;  // --components names the region
	ComponentLevel level;
	std::size_t samples;
	Eigen::Index points;
};

// The region's PCA records; returns how many basis columns are kept.
Eigen::Index readRegionPca(Reader& r, RegionModel& rm, const RegionLoad& ld, std::vector<double>& eig) {
	const bool bases = ld.bases, reduce = ld.reduce;
	const std::size_t samples = ld.samples;
	const Eigen::Index n = 3 * rm.pixelCount() + 2 * ld.points;
	auto count = [&](const std::string& name, double maxValue) { return countOf(r, name, maxValue); };
	// The mean and scale of the combined vectors serve projection and the basis product only: a render
	// load (which uses the appearance cache) skips them, unless the region is reduced.
	auto vectorInto = [&](const std::string& name, Eigen::VectorXf& v) {
		if (!bases && !reduce) {
			r.skip(name, Type::F32, 4);
			return;
		}
		r.arrayInto<float>(name, Type::F32, [&](std::size_t count) {
			if (Eigen::Index(count) != n) r.fail("region '" + rm.name + "' " + name + " has the wrong size");
			v.resize(n);
			return v.data();
		});
	};
	vectorInto("mean", rm.pca.mean);
	vectorInto("sigma", rm.pca.sigma);
	eig = r.f64("eigenvalues");
	const Eigen::Index l = Eigen::Index(count("components", 1e7));
	if (Eigen::Index(eig.size()) < l) r.fail("region '" + rm.name + "' arrays have inconsistent sizes");
	rm.pca.eigenvalues = Eigen::Map<Eigen::VectorXd>(eig.data(), Eigen::Index(eig.size()));
	Eigen::Index kept = l;  // basis columns held
	if (reduce) {
		const ComponentLevel& lv = ld.level;
		if (lv.count > 0) {
			if (lv.count > l)
				throw Error(r.path(), 0, "{{components}} asks for " + std::to_string(lv.count) + " components of region '" + rm.name + "', which keeps " +
				                             std::to_string(l));
			kept = Eigen::Index(lv.count);
		} else {
			kept = lv.evr >= 1.0 ? l : std::min(l, std::max<Eigen::Index>(1, rm.pca.componentsFor(lv.evr)));
		}
	}
	if (!bases && !reduce) {
		r.skip("basis", Type::F32, 4);
		r.skip("coefficients", Type::F32, 4);
	} else {
		if (bases) {
			r.arrayInto<float>("basis", Type::F32, [&](std::size_t count) {
				if (Eigen::Index(count) != n * l) r.fail("region '" + rm.name + "' basis has the wrong size");
				rm.pca.basis.resize(n, l);
				return rm.pca.basis.data();
			});
		} else {  // the first `kept` columns (column-major: a prefix), the rest only hashed
			const std::size_t count = r.expect("basis", Type::F32, 4);
			if (Eigen::Index(count) != n * l) r.fail("region '" + rm.name + "' basis has the wrong size");
			rm.pca.basis.resize(n, kept);
			r.raw(rm.pca.basis.data(), std::size_t(n * kept) * 4);
			r.readThrough(std::size_t(n * (l - kept)) * 4);
			r.endRecord();
		}
		r.arrayInto<float>("coefficients", Type::F32, [&](std::size_t count) {
			if (count != samples * std::size_t(l)) r.fail("region '" + rm.name + "' coefficients have the wrong size");
			rm.pca.trainingCoefficients.resize(Eigen::Index(samples), l);
			return rm.pca.trainingCoefficients.data();
		});
	}
	return kept;
}

// The region's appearance cache: in memory (a full load, every sample checked) or left on disk behind a
// source that reads and checks each sample (a render; `fd` is shared by the regions).
void readRegionAppearances(Reader& r, RegionModel& rm, const RegionLoad& ld, std::shared_ptr<int>& fd) {
	const bool bases = ld.bases;
	const std::size_t samples = ld.samples;
	const std::size_t q3 = std::size_t(3 * rm.pixelCount());
	std::uint64_t cacheOffset = 0;
	std::size_t cacheCount = 0;
	if (!bases) {  // render: the cache stays on disk, read per sample through its checksums
		cacheCount = r.expect("appearances", Type::U8, 1);
		cacheOffset = r.position();
		r.skipData(cacheCount + 8);
	} else {
		r.arrayInto<std::uint8_t>("appearances", Type::U8, [&](std::size_t count) {
			cacheCount = count;
			resizePrefaulted(rm.sampleAppearances, count);
			return rm.sampleAppearances.data();
		});
	}
	if (cacheCount != 0 && cacheCount != samples * q3) r.fail("region '" + rm.name + "' appearance cache has the wrong size");
	auto sums = r.u64("appearanceChecksums");
	if (sums.size() != (cacheCount ? samples : 0)) r.fail("region '" + rm.name + "' appearance checksums have the wrong size");
	// A full load verifies every sample against its own checksum too, as a render does for the samples it
	// reads: both loads agree on what is damaged.
	for (std::size_t i = 0; bases && i < sums.size(); ++i)
		if (checksum64(&rm.sampleAppearances[i * q3], q3) != sums[i])
			r.fail("checksum mismatch in the cached appearance of sample " + std::to_string(i) + " (region " + rm.name + ")");
	if (!bases && cacheCount) {
		if (!fd) {
			const int raw = ::open(r.path().c_str(), O_RDONLY | O_CLOEXEC);
			if (raw < 0) r.fail(std::string("cannot reopen: ") + std::strerror(errno));
			fd = std::shared_ptr<int>(new int(raw), [](int* p) {
				::close(*p);
				delete p;
			});
		}
		rm.appearanceSource = std::make_shared<FileAppearanceSource>(fd, r.path(), cacheOffset, q3, std::move(sums), rm.name);
	}
}

RegionModel readRegion(Reader& r, const FaceModel& m, RegionLoad ld, const ComponentLevels& levels, std::shared_ptr<int>& fd) {
	auto one = [&](const std::string& name) { return oneString(r, name); };
	const bool bases = ld.bases;
	RegionModel rm;
	rm.name = one("name");
	rm.pixels = r.i32("pixels");
	for (auto p : rm.pixels)
		if (p < 0 || std::int64_t(p) >= std::int64_t(m.width) * m.height) r.fail("region pixel index out of range");
	rm.alpha = r.f32("alpha");
	if (rm.alpha.size() != rm.pixels.size()) r.fail("region '" + rm.name + "' arrays have inconsistent sizes");
	const auto level = levels.find(rm.name);
	ld.reduce = level != levels.end();
	if (ld.reduce) ld.level = level->second;
	std::vector<double> eig;
	const Eigen::Index kept = readRegionPca(r, rm, ld, eig);
	readRegionAppearances(r, rm, ld, fd);
	const bool reduce = ld.reduce;
	const std::size_t q3 = std::size_t(3 * rm.pixelCount());
	if (reduce) {
		if (bases) {  // a full load keeps its PCA; the source gets copies
			rm.appearanceSource = std::make_shared<ReducedAppearanceSource>(rm.pca.mean, rm.pca.sigma, rm.pca.basis.leftCols(kept),
			                                                                rm.pca.trainingCoefficients, Eigen::Index(q3), kept);
		} else {  // a render holds only the reduced source (the kept columns move into it)
			rm.appearanceSource = std::make_shared<ReducedAppearanceSource>(std::move(rm.pca.mean), std::move(rm.pca.sigma), std::move(rm.pca.basis),
			                                                                std::move(rm.pca.trainingCoefficients), Eigen::Index(q3), kept);
			rm.pca = CorrelationPca{};
			rm.pca.eigenvalues = Eigen::Map<Eigen::VectorXd>(eig.data(), Eigen::Index(eig.size()));
		}
		rm.sampleAppearances.clear();
		rm.sampleAppearances.shrink_to_fit();
	}
	return rm;
}

FaceModel readRecords(Reader& r, bool bases, std::uint32_t version, const ComponentLevels& levels) {
	FaceModel m;
	m.scheme = readSchemeRecords(r, version);
	readShapeRecords(r, version, m);
	const std::int64_t regions = countOf(r, "regions", 64);
	std::shared_ptr<int> fd;  // shared by the regions' on-disk appearance caches
	const RegionLoad load{bases, false, {}, m.samples.size(), Eigen::Index(m.scheme.pointNames.size())};
	for (std::int64_t i = 0; i < regions; ++i) m.regions.push_back(readRegion(r, m, load, levels, fd));
	if (!r.atEnd()) r.fail("trailing data after the last record");
	for (const auto& [name, level] : levels) {
		if (m.regionIndex(name) >= 0) continue;
		std::string names;
		for (const auto& rg : m.regions) names += (names.empty() ? "" : ", ") + rg.name;
		throw Error(r.path(), 0, "{{components}} names region '" + name.substr(0, 40) + "', which this model does not have (regions: " + names + ")");
	}
	return m;
}

}  // namespace

}  // namespace talkhead
