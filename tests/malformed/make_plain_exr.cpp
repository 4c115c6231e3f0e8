// Writes no-vts-channels.exr: a valid EXR (one float channel R, 16 x 2) that is not a vts profile file.
#include <ImfOutputFile.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <vector>
int main() {
  const int w = 16, h = 2;
  Imf::Header hdr(w, h);
  hdr.channels().insert("R", Imf::Channel(Imf::FLOAT));
  std::vector<float> px(w * h, 0.5f);
  Imf::OutputFile f("no-vts-channels.exr", hdr);
  Imf::FrameBuffer fb;
  fb.insert("R", Imf::Slice(Imf::FLOAT, (char*)px.data(), sizeof(float), sizeof(float) * w));
  f.setFrameBuffer(fb);
  f.writePixels(h);
}
