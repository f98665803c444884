// SPDX-License-Identifier: GPL-3.0-or-later
// A job written as JSON (src/perform/job.cpp: what `talkhead job` and batch's children read). Besides
// surviving any input, a job read back from what jobJson writes is itself written and read back unchanged.
#include <string>

#include "fuzz_support.h"
#include "perform/job.h"

using namespace talkhead;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
	const std::string text(reinterpret_cast<const char*>(data), size);
	Job job;
	bool parsed = false;
	fuzz::expectOnlyErrors([&] {
		job = parseJob(text, "fuzz.json");
		parsed = true;
	});
	if (!parsed) return 0;
	try {
		// jobJson gathers a repeated field at its first place: one round normalises, the next keeps it.
		const Job once = parseJob(jobJson(job), "once");
		const Job twice = parseJob(jobJson(once), "twice");
		TALKHEAD_FUZZ_CHECK(once.command == job.command && twice.command == once.command && twice.fields == once.fields, jobJson(once));
		TALKHEAD_FUZZ_CHECK(once.fields.size() == job.fields.size(), jobJson(once));
	} catch (const std::exception& e) {
		fuzz::violated("jobJson output reads back", e.what());
	}
	return 0;
}
