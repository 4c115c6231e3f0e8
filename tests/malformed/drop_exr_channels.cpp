// Copies a vts profile EXR, dropping the channels named on the command line.
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <set>
#include <string>
#include <vector>
int main(int argc, char** argv) {
  Imf::InputFile in(argv[1]);
  Imf::Header hdr = in.header();
  const Imath::Box2i dw = hdr.dataWindow();
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  std::set<std::string> drop(argv + 3, argv + argc);
  Imf::ChannelList kept;
  for (auto it = hdr.channels().begin(); it != hdr.channels().end(); ++it)
    if (!drop.count(it.name())) kept.insert(it.name(), it.channel());
  hdr.channels() = kept;
  std::vector<std::vector<char>> bufs;
  Imf::FrameBuffer rfb, wfb;
  for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
    const int sz = it.channel().type == Imf::HALF ? 2 : 4;
    const int xs = it.channel().xSampling, ys = it.channel().ySampling;
    const int cw = w / xs, ch = h / ys;
    bufs.emplace_back(std::size_t(cw) * ch * sz);
    char* base = bufs.back().data();  // the data window starts at (0, 0) in vts files
    Imf::Slice s(it.channel().type, base, sz, std::size_t(sz) * cw, xs, ys);
    rfb.insert(it.name(), s);
    if (!drop.count(it.name())) wfb.insert(it.name(), s);
  }
  in.setFrameBuffer(rfb);
  in.readPixels(dw.min.y, dw.max.y);
  Imf::OutputFile out(argv[2], hdr);
  out.setFrameBuffer(wfb);
  out.writePixels(h);
}
