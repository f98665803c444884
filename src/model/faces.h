// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talkhead {

// The real faces that ship with talkhead (issue 48, D91): models/faces/faces.tsv names each one, its clips
// and their licence; the model is built on first use into the user's cache (track/face_build.h builds it).
struct ShippedFace {
	std::string name;        // "grid-s4"
	int width = 0, height = 0;  // the clips' frame size
	std::string lang;        // the clips' language ("en-US")
	std::vector<std::string> emotions;  // recorded, in take order
	std::string licence, source;
	std::string takes;       // the take list's path
};

// Every shipped face, in the registry's order (none when the registry is not installed). Throws Error
// naming the registry when it is malformed.
std::vector<ShippedFace> shippedFaces();
// The shipped face of that name; Error listing the names when there is none.
ShippedFace shippedFace(const std::string& name);

// Where the face's model is kept once built: <cache>/models/faces/NAME.thm ("" when no cache folder is
// known), and the recipe stamp beside it (NAME.recipe).
std::string shippedFaceModelPath(const ShippedFace& face);
// What the model is built from: the take list's text, each file's name and size, and the builder's
// version. A model whose stamp differs is built again.
std::string shippedFaceRecipe(const ShippedFace& face);
// The model's path when it is built from the current recipe; nullopt when it must be built.
std::optional<std::string> builtShippedFace(const ShippedFace& face);

// Faces people made themselves (`face create --name NAME`, issue 48 part 3): NAME.thm in
// <cache>/models/faces/own/ with NAME.info beside it (size, emotions, source: one "key\tvalue" a line).
struct OwnFace {
	std::string name, model, size, emotions, source;
};
std::string ownFacesDir();  // "" when no cache folder is known
std::vector<OwnFace> ownFaces();  // sorted by name
std::optional<OwnFace> ownFace(const std::string& name);
// A name `face create --name` may take: 1–40 of [A-Za-z0-9._-], not starting with '.', not a shipped
// face's or "synthetic". Throws Error saying why not.
void checkOwnFaceName(const std::string& name);

}  // namespace talkhead
