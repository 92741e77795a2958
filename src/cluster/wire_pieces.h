// Conventional mode's part of the wire (wire_pieces.cpp): frame specs and piece orders inside a
// Control message; Results are declared in wire.h with the other messages.
#pragma once
#include "cluster/wire.h"
#include "cluster/wire_io.h"

namespace frameless::cluster {

// Writes / reads Control::frame (when set) and Control::pieces (when not empty), in that order.
void put_frame_and_pieces(wire_io::Writer& w, const Control& m);
void get_frame_and_pieces(wire_io::Reader& r, Control& m, bool frame, bool pieces);

// Whether in[0..4) is the one RGBE encoding of its colour (decoders accept nothing else).
bool canonical_rgbe(const uint8_t in[4]);

}  // namespace frameless::cluster
