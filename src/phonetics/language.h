// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "phonetics/cdv.h"
#include "phonetics/emotion.h"
#include "phonetics/transcript.h"

namespace talkhead {

// A phone of a language's inventory (phonetics/<lang>/inventory.tsv).
struct PhoneInfo {
	std::string phone;  // canonical IPA
	std::string kind;   // vowel | consonant | liquid | glide | pause
	std::string group;  // consonants: the CDV group key (first phone of the homorganic group), else "-"
	char vclass = 0;    // vowels and glides: context class 'i', 'a' or 'u'; 0 otherwise
	std::optional<Cdv> cdv;  // fixed CDV (vowels, glides, pauses, fixed consonants), or none (decided by context)
};

// How a transcript spells its phones (the `notation` column of phonetics/<lang>/symbols.tsv). Auto: decided
// per transcript from the evidence in its labels (detectNotation). Xsampa covers SAMPA, which it extends;
// Br1 is MBROLA's br1/br2/br3 Brazilian Portuguese set.
enum class Notation { Auto, Ipa, Arpabet, Xsampa, Espeak, Praat, Br1 };
std::optional<Notation> parseNotation(const std::string& name);  // ipa sampa xsampa arpabet espeak praat br1 auto
std::string notationName(Notation n);                            // "ipa", "arpabet", "x-sampa", …

// Language data: the phone inventory and every accepted spelling of each phone (IPA, X-SAMPA, espeak
// mnemonics, Praat trigraphs, ARPAbet …) → canonical IPA phones. Loaded from phonetics/<tag>/.
class Language {
public:
	// A language's table: "pt-BR", "en-US", "de", "es", "fr", "it" (case-insensitive; a region the tables do
	// not split, e.g. "fr-CA", reads as its language), or a language generic() has mapped; throws Error.
	static const Language& get(const std::string& tag);
	// `tag` mapped through phonetics/generic (the union of the tables' IPA spellings) — for a language
	// without a table (--generic-visemes); later get(tag) calls return it too. Throws Error.
	static const Language& generic(const std::string& tag);
	static std::vector<std::string> available();
	Language(const std::string& tag, const std::string& dir);

	const std::string& tag() const { return tag_; }
	// Canonical phones for a label (a diphthong or affricate may give two); nullopt if unknown. Auto: any
	// notation, the first row of the file winning where spellings collide (ARPAbet's single capitals in
	// en-US); otherwise the notation's own spellings first, then the IPA and pause ones (ARPAbet and
	// espeak case-insensitively; SAMPA, X-SAMPA and br1 exactly, as their case carries meaning).
	std::optional<std::vector<std::string>> normalize(const std::string& label, Notation notation = Notation::Auto) const;
	// The notations this language's table has spellings for.
	std::vector<Notation> notations() const;
	// The phones of the known spelling closest to an unknown label (--unknown nearest), or nullopt: the label
	// without stress, length, modifier letters, diacritics or hooks (ˈaː, tʰ, t͡ʃ, ɐ̃ as ɐ̃ then ɐ, ɗ), else the spelling at
	// edit distance 1 (labels of 2–4 characters) or 2 (5–16) when all spellings as near agree; never a pause,
	// never for a label of one character or more than 16. `near` gets the disagreeing candidates.
	std::optional<std::vector<std::string>> nearest(const std::string& label, Notation notation = Notation::Auto, std::string* near = nullptr) const;
	const PhoneInfo& info(const std::string& phone) const;
	// The inventory, for messages.
	std::string inventoryList() const;

private:
	std::string tag_;
	std::map<std::string, PhoneInfo> inventory_;
	std::vector<std::string> order_;
	std::map<std::string, std::vector<std::string>> symbols_, symbolsFolded_;
	std::map<Notation, std::map<std::string, std::vector<std::string>>> byNotation_, byNotationFolded_;
};

// The notation of a phone-level transcript's labels, decided from the evidence in them: the notation under
// which most labels are known wins; when two read the same labels equally well but differently (a file
// of only "S T" is ARPAbet [s t] or SAMPA [ʃ θ]), it is an Error asking for the notation field. `evidence` gets a
// few labels that decided it. MBROLA .pho files are SAMPA/X-SAMPA or br1 (never ARPAbet).
Notation detectNotation(const Transcript& transcript, const Language& language, std::string* evidence = nullptr);

enum class UnknownPhone { Error, Nearest, Silence };

// One phone of the utterance with its CDV.
struct PhoneSegment {
	Ticks start{0}, end{0};
	std::string label;  // as in the transcript
	std::string phone;  // canonical IPA ("_" = pause)
	Cdv cdv;            // keypose class (phonetics/visemes.tsv)
	long line = 0;
};

// Normalises a phone-, word- or viseme-level transcript to phones with CDVs (spec §2.5 and
// docs/decisions.md): word level goes through espeak-ng; viseme level maps through
// phonetics/viseme-input.tsv; an interval whose label expands to N phones is split into N equal parts.
// Phone-level labels are read in `notation` (Auto: detectNotation; the choice is written to *used).
std::vector<PhoneSegment> phoneSegments(const Transcript& transcript, const Language& language, UnknownPhone unknown = UnknownPhone::Error,
                                        Notation notation = Notation::Auto, Notation* used = nullptr);

// The context-dependent viseme rule (spec §2.5) over a phone sequence: vowels by table, [i] → <i2>
// between two [t d n] or two [ʃ ʒ]; consonants by the V1 C V2 / C V context looked up in the group's
// contexts (phonetics/visemes.tsv), the right vowel searched up to 2 phones ahead over liquids/glides.
void assignCdvs(std::vector<PhoneSegment>& phones, const Language& language);

// A keypose: a CDV at an instant (the midpoint of its phone, thesis Eq. 5.1).
struct Keypose {
	Ticks time{0};
	Cdv cdv;
	std::size_t first = 0, last = 0;  // the phone segments it stands for
	bool breath = false;              // the in-breath before speech (PauseStyle::Natural), not a phone's viseme
	// The lips held before the first words (PauseStyle::Still, D70): the rest mouth, or with a
	// coarticulation model the real speakers' opening there (CoarticulationModel::leadOpening).
	bool hold = false;
	// Phones around it, as a corpus row writes them (spec §1.2): two before, its own (the run's first),
	// two after; "_" for a pause or the utterance's edge. A model with several samples of the CDV uses the
	// one whose context matches best (FaceModel::findSample).
	std::array<std::string, 5> context{"_", "_", "_", "_", "_"};
	// Set per keypose by an emotion track (render controls); unset: the performance's.
	std::optional<Emotion> emotion{};
	std::optional<double> intensity{};
	// A specific sample of the model (render --drive-mouth: the actor's exemplar nearest the driver's
	// mouth, D55); −1: resolved from (emotion, CDV, context).
	long sample = -1;
	// The coarticulation model's inner-lip opening for this keypose (D62), in units of a speaker's 90th
	// percentile in speech; the face shows its exemplar nearest it (chooseMouthExemplars). Unset: the CDV's.
	std::optional<double> mouthOpening{};
	std::optional<double> mouthWidth{};  // the same for the mouth's width (1 = the speaker's median in speech)
	// The inner-lip opening (eye distances) the chosen exemplar is drawn at (D100: drawOpening): its lower lip
	// and jaw moved so the mouth opens as predicted, not as wide as the nearest sample happens to. Unset: the sample's own.
	std::optional<double> drawnOpening{};
};

// How pauses move the mouth (docs/decisions.md D34).
//  Thesis: one silence keypose at the pause's midpoint, like any phone (Eq. 5.1).
//  Natural (default): in a pause longer than kPauseShort the mouth reaches rest kRestAfter after the
//  speech stops and holds it; before speech that follows a pause of at least kBreathPause it breathes in
//  (lips parted, the central-vowel CDV kBreathCdv, kBreathLead before the first phone, after rest until
//  kBreathLead + kBreathRise); a shorter pause leaves rest kRestBefore before the next phone.
//  Still (issue 32, D62, D70; the default with a coarticulation model): before the first words one mouth
//  held still (Keypose::hold) from the start until kStillLead before the first phone, whatever the pause's
//  length; after speech rest, held; before later speech an in-breath that rises over up to 2 × kBreathRise
//  where the pause allows one, else rest held until kStillLead before the next phone.
enum class PauseStyle { Natural, Thesis, Still };
inline constexpr Ticks kRestAfter{kTicksPerSecond * 12 / 100};    // 0.12 s
inline constexpr Ticks kRestBefore{kTicksPerSecond * 30 / 100};   // 0.30 s
inline constexpr Ticks kPauseShort = kRestAfter + kRestBefore;    // 0.42 s
inline constexpr Ticks kBreathLead{kTicksPerSecond * 30 / 100};   // 0.30 s
inline constexpr Ticks kBreathRise{kTicksPerSecond * 15 / 100};   // 0.15 s
inline constexpr Ticks kBreathPause = kBreathLead + kBreathRise;  // 0.45 s
inline constexpr const char* kBreathCdv = "ɐ";
inline constexpr Ticks kStillLead{kTicksPerSecond * 15 / 100};   // 0.15 s

// "natural" / "thesis" → PauseStyle; nullopt for anything else.
std::optional<PauseStyle> parsePauseStyle(const std::string& name);

// One keypose per phone at its midpoint, with the project's edge rules (docs/decisions.md): runs of the
// same CDV merge into one keypose at the run's midpoint; a keypose less than one frame after the previous
// one is dropped unless its phone is longer (then it replaces the previous one); pauses as `pauses` says.
bool bilabial(const std::string& cdv);  // p1, p2: the CDVs whose lips shut
// `keepBilabials` (with a coarticulation model, D90): a /p b m/ keypose is never the one dropped — the
// lips' closure is what a viewer checks the sync by — so a 30-ms /p/ before a 34-ms /l/ at 25 fps shuts.
std::vector<Keypose> keyposes(const std::vector<PhoneSegment>& phones, Ticks frame, PauseStyle pauses = PauseStyle::Natural,
                              bool keepBilabials = false);

}  // namespace talkhead
