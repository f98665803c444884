// SPDX-License-Identifier: GPL-3.0-or-later
#include "perform/job.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "base/error.h"
#include "base/json.h"

namespace talkhead {

std::optional<std::string> jobValue(const std::vector<JobField>& fields, const std::string& field) {
	std::optional<std::string> v;
	for (const JobField& f : fields)
		if (f.field == field) v = f.value.value_or("");
	return v;
}

std::string jobJson(const Job& job) {
	// Repeated fields gathered into one array at their first place.
	std::vector<std::string> order;
	std::map<std::string, std::vector<const JobField*>> byName;
	for (const JobField& f : job.fields) {
		if (!byName.count(f.field)) order.push_back(f.field);
		byName[f.field].push_back(&f);
	}
	JsonObject fields;
	for (const std::string& name : order) {
		const auto& all = byName[name];
		auto one = [](const JobField* f) { return f->value ? jsonQuote(*f->value) : std::string("true"); };
		if (all.size() == 1) {
			fields.raw(name, one(all[0]));
			continue;
		}
		JsonArray values;
		for (const JobField* f : all) values.raw(one(f));
		fields.raw(name, values.str());
	}
	return JsonObject().add("command", job.command).raw("fields", fields.str()).str();
}

namespace {

bool fieldName(const std::string& s) {
	return !s.empty() && s.front() != '-' &&
	       std::all_of(s.begin(), s.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-'; });
}

// One value of a field, appended to `out`; false and null leave it out.
void addValue(const std::string& name, const JsonValue& v, const std::string& where, std::vector<JobField>& out) {
	switch (v.kind) {
	case JsonValue::Kind::String:
		out.push_back({name, v.string});
		return;
	case JsonValue::Kind::Number: {
		char b[40];
		std::snprintf(b, sizeof b, "%.17g", v.number);
		out.push_back({name, std::string(b)});
		return;
	}
	case JsonValue::Kind::Bool:
		if (v.boolean) out.push_back({name, std::nullopt});
		return;
	case JsonValue::Kind::Null:
		return;
	default:
		throw Error(where + ": '" + name + "' must be a string, a number, true or false (or an array of them)");
	}
}

}  // namespace

Job parseJob(const std::string& text, const std::string& name) {
	const JsonValue root = parseJson(text, name, 1, 100000);
	if (root.kind != JsonValue::Kind::Object) throw Error(name + ": a job is a JSON object {\"command\": …, \"fields\": {…}}");
	for (const auto& [k, v] : root.object)
		if (k != "command" && k != "fields") throw Error(name + ": unknown member '" + k + "' (a job has 'command' and 'fields')");
	Job job;
	const JsonValue* command = root.find("command");
	if (!command || command->kind != JsonValue::Kind::String || command->string.empty())
		throw Error(name + ": 'command' must name the command (\"render\", \"say\", …)");
	job.command = command->string;
	const JsonValue* fields = root.find("fields");
	if (!fields) return job;
	if (fields->kind != JsonValue::Kind::Object) throw Error(name + ": 'fields' must be an object of field names and values");
	for (const auto& [k, v] : fields->object) {
		if (!fieldName(k)) throw Error(name + ": '" + k + "' is not a field name (lower-case letters, digits and '-')");
		if (v.kind != JsonValue::Kind::Array) {
			addValue(k, v, name, job.fields);
			continue;
		}
		for (const JsonValue& item : v.array) {
			if (item.kind == JsonValue::Kind::Array) throw Error(name + ": '" + k + "' holds an array inside an array");
			addValue(k, item, name, job.fields);
		}
	}
	return job;
}

}  // namespace talkhead
