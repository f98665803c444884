// SPDX-License-Identifier: GPL-3.0-or-later
// The `talkhead` Python module's native part (issue 33, decision D63): talkhead's commands run in
// process with the GIL released, errors as Python exceptions with the command line's message, progress
// through a callback, and a render's frames as numpy arrays from an iterator.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include "base/cpu_floor.h"
#include "base/error.h"
#include "cli/commands.h"
#include "cli/run.h"
#include "render/frame_sink.h"

namespace py = pybind11;
using namespace talkhead;

namespace {

// Raised from a sink to stop a render its caller no longer wants (no output is committed).
struct Cancelled : std::exception {
	const char* what() const noexcept override { return "cancelled"; }
};

PyObject* errorType = nullptr;       // talkhead.Error
PyObject* usageErrorType = nullptr;  // talkhead.UsageError (a subclass)

[[noreturn]] void raise(int status, const std::string& line) {
	// The command line's one line, without its "talkhead: " / "talkhead: error: " prefix.
	std::string message = line;
	for (const char* prefix : {"talkhead: error: ", "talkhead: "})
		if (message.rfind(prefix, 0) == 0) {
			message = message.substr(std::strlen(prefix));
			break;
		}
	PyErr_SetString(status == 2 ? usageErrorType : errorType, message.c_str());
	throw py::error_already_set();
}

// Progress: calls `fn(done, total)` with the GIL after each frame; an exception there stops the render.
class ProgressSink final : public FrameSink {
public:
	explicit ProgressSink(py::object fn) : fn_(std::move(fn)) {}
	void begin(const StreamInfo& info) override { total_ = info.frames; }
	void frame(const RenderedFrame& f) override {
		py::gil_scoped_acquire gil;
		try {
			fn_(f.index + 1, total_);
		} catch (py::error_already_set& e) {
			error_ = std::move(e);
			throw Cancelled();
		}
	}
	std::optional<py::error_already_set> error_;

private:
	py::object fn_;
	std::int64_t total_ = 0;
};

void run(const std::vector<std::string>& args, const py::object& progress) {
	std::unique_ptr<ProgressSink> sink = progress.is_none() ? nullptr : std::make_unique<ProgressSink>(progress);
	int status = 0;
	std::string error;
	{
		py::gil_scoped_release release;
		cli::setExtraFrameSink(sink.get());
		status = cli::runCommandLine(args, error);
		cli::setExtraFrameSink(nullptr);
	}
	if (sink && sink->error_) throw std::move(*sink->error_);
	if (status != 0) raise(status, error);
}

// A job written as JSON (Python's keywords as the command's fields, perform/job.h) as its command line.
std::vector<std::string> jobArgs(const std::string& json) {
	try {
		return cli::jobCommandLine(json, "the job");
	} catch (const std::exception& e) {
		raise(1, e.what());
	}
}

void runJob(const std::string& json, const py::object& progress) { run(jobArgs(json), progress); }

// A render's frames, produced by a thread running the command, consumed in order by the iterator.
class FrameStream {
public:
	explicit FrameStream(std::vector<std::string> args) : args_(std::move(args)) {
		worker_ = std::thread([this] {
			// --background transparent: RGBA frames, the face's matte as alpha (as the PNGs of --frames).
			bool alpha = false;
			for (std::size_t i = 0; i + 1 < args_.size(); ++i) alpha = alpha || (args_[i] == "--background" && args_[i + 1] == "transparent");
			QueueSink sink(*this, alpha);
			cli::setExtraFrameSink(&sink);
			std::string error;
			const int status = cli::runCommandLine(args_, error);
			cli::setExtraFrameSink(nullptr);
			std::lock_guard<std::mutex> lock(mutex_);
			status_ = status, error_ = error, done_ = true;
			changed_.notify_all();
		});
	}
	~FrameStream() { close(); }

	py::tuple next() {
		Frame f;
		{
			std::unique_lock<std::mutex> lock(mutex_);
			while (queue_.empty() && !done_) {
				{
					py::gil_scoped_release release;
					changed_.wait_for(lock, std::chrono::milliseconds(100));
				}
				if (PyErr_CheckSignals() != 0) {  // Ctrl-C: stop the render, then raise
					lock.unlock();
					close();
					throw py::error_already_set();
				}
			}
			if (queue_.empty()) {
				lock.unlock();
				finish();
				if (status_ != 0 && !cancelled_) raise(status_, error_);
				throw py::stop_iteration();
			}
			f = std::move(queue_.front());
			queue_.pop_front();
			changed_.notify_all();
		}
		py::array_t<std::uint8_t> image({f.height, f.width, f.channels});
		std::memcpy(image.mutable_data(), f.rgb.data(), f.rgb.size());
		return py::make_tuple(f.index, f.seconds, image);
	}
	void close() {
		{
			std::lock_guard<std::mutex> lock(mutex_);
			if (!done_) cancelled_ = true;
			changed_.notify_all();
		}
		py::gil_scoped_release release;
		finish();
	}

private:
	struct Frame {
		std::int64_t index = 0;
		double seconds = 0;
		int width = 0, height = 0, channels = 3;
		std::vector<std::uint8_t> rgb;  // RGB, or RGBA (channels 4)
	};
	class QueueSink final : public FrameSink {
	public:
		QueueSink(FrameStream& s, bool alpha) : s_(s), alpha_(alpha) {}
		bool needsRgb() const override { return true; }
		bool needsAlpha() const override { return alpha_; }
		void frame(const RenderedFrame& f) override {
			Frame x{f.index, toSeconds(f.time), f.rgb->width, f.rgb->height, 3, {}};
			if (alpha_ && f.yuv->a.size() == std::size_t(x.width) * std::size_t(x.height)) {
				x.channels = 4;
				x.rgb.resize(f.yuv->a.size() * 4);
				for (std::size_t i = 0; i < f.yuv->a.size(); ++i) {
					std::memcpy(&x.rgb[4 * i], &f.rgb->data[3 * i], 3);
					x.rgb[4 * i + 3] = f.yuv->a[i];
				}
			} else {
				x.rgb = f.rgb->data;
			}
			std::unique_lock<std::mutex> lock(s_.mutex_);
			s_.changed_.wait(lock, [&] { return s_.queue_.size() < kAhead || s_.cancelled_; });
			if (s_.cancelled_) throw Cancelled();
			s_.queue_.push_back(std::move(x));
			s_.changed_.notify_all();
		}

	private:
		FrameStream& s_;
		bool alpha_;
	};
	static constexpr std::size_t kAhead = 8;  // frames drawn ahead of the consumer
	std::vector<std::string> args_;
	std::thread worker_;
	std::mutex mutex_;
	std::condition_variable changed_;
	std::deque<Frame> queue_;
	bool done_ = false, cancelled_ = false;
	int status_ = 0;
	std::string error_;
	void finish() {
		if (worker_.joinable()) worker_.join();
	}
};

}  // namespace

PYBIND11_MODULE(_talkhead, m) {
	// A CPU below the build's floor (x86-64-v3 for the portable build): an ImportError that says so (D74).
	if (const char* missing = talkhead::cpuFloorMissing()) throw py::import_error(missing);
	m.doc() = "talkhead's native part: the commands in process (see the talkhead package)";
	static py::exception<talkhead::Error> error(m, "Error", PyExc_RuntimeError);
	static py::exception<std::invalid_argument> usage(m, "UsageError", error.ptr());
	errorType = error.ptr();
	usageErrorType = usage.ptr();
	m.def("run", &run, py::arg("args"), py::arg("progress") = py::none(),
	      "Runs one talkhead command (args as on the command line, the command first); raises Error (UsageError for a usage error) with its message.");
	m.def("run_job", &runJob, py::arg("job"), py::arg("progress") = py::none(),
	      "Runs a job written as JSON ({\"command\": …, \"fields\": {…}}: the command's options by name, as `talkhead job` reads it).");
	py::class_<FrameStream>(m, "FrameStream")
	    .def(py::init<std::vector<std::string>>(), py::arg("args"))
	    .def_static("of_job", [](const std::string& json) { return std::make_unique<FrameStream>(jobArgs(json)); }, py::arg("job"))
	    .def("__iter__", [](FrameStream& s) -> FrameStream& { return s; })
	    .def("__next__", &FrameStream::next)
	    .def("close", &FrameStream::close);
}
