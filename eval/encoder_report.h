#pragma once
// What the table notes say about the FMD motion encoder in use: where it came from and how well
// its autoencoder reconstructs motion, as the paper reports for its own (§V: per-frame position
// and rotation error on the training subject and on validation subjects). deixis-train writes
// those figures into the encoder's manifest (AutoEncoder.manifest.json, next to the weights).

#include <filesystem>
#include <string>

namespace deixis::eval {

// One line for the notes: "FMD encoder, right hand (<path>): reconstruction per frame …", or, when
// the manifest is missing or has no reconstruction figures, a line saying so. `hand` is "right" or
// "left". Never throws for a bad manifest: the line says what is wrong with which file.
std::string describe_encoder(const std::filesystem::path& encoder_weights, const std::string& hand);

}  // namespace deixis::eval
