// Private to src/io/tiff_io.cpp: the libtiff functions it calls, taken from the library loaded
// at the first TIFF read or written (tiff_api.cpp), so that a run without TIFFs never maps
// libtiff. After this header, libtiff's names (TIFFGetField, ...) call the loaded functions.
#pragma once

#include <tiffio.h>

namespace fss {

// Every libtiff function fss calls, as X(member): the function TIFF<member>.
// clang-format off
#define FSS_TIFF_FUNCTIONS(X)                                                                   \
  X(ClientOpenExt) X(Close) X(DefaultStripSize) X(FindCODEC) X(Flush) X(GetField)               \
  X(GetFieldDefaulted) X(IsCODECConfigured) X(IsTiled) X(LastDirectory) X(OpenOptionsAlloc)     \
  X(OpenOptionsFree) X(OpenOptionsSetErrorHandlerExtR) X(OpenOptionsSetMaxSingleMemAlloc)       \
  X(OpenOptionsSetWarningHandlerExtR) X(ReadScanline) X(ReadTile) X(ScanlineSize)               \
  X(SetErrorHandler) X(SetErrorHandlerExt) X(SetField) X(SetWarningHandler)                     \
  X(SetWarningHandlerExt) X(TileSize) X(WriteScanline)
// clang-format on

// One pointer a function, with libtiff's own signature.
struct TiffApi {
// A declaration: its argument is a name, which parentheses would break.
// NOLINTNEXTLINE(bugprone-macro-parentheses)
#define FSS_TIFF_MEMBER(member) decltype(&::TIFF##member) member = nullptr;
  FSS_TIFF_FUNCTIONS(FSS_TIFF_MEMBER)
#undef FSS_TIFF_MEMBER
};

// libtiff's functions, the library loaded at the first call; an fss::Error (runtime) "cannot
// load libtiff: ... (install ...)" when it or one of its functions is missing.
const TiffApi& tiff_api();

}  // namespace fss

#define TIFFClientOpenExt ::fss::tiff_api().ClientOpenExt
#define TIFFClose ::fss::tiff_api().Close
#define TIFFDefaultStripSize ::fss::tiff_api().DefaultStripSize
#define TIFFFindCODEC ::fss::tiff_api().FindCODEC
#define TIFFFlush ::fss::tiff_api().Flush
#define TIFFGetField ::fss::tiff_api().GetField
#define TIFFGetFieldDefaulted ::fss::tiff_api().GetFieldDefaulted
#define TIFFIsCODECConfigured ::fss::tiff_api().IsCODECConfigured
#define TIFFIsTiled ::fss::tiff_api().IsTiled
#define TIFFLastDirectory ::fss::tiff_api().LastDirectory
#define TIFFOpenOptionsAlloc ::fss::tiff_api().OpenOptionsAlloc
#define TIFFOpenOptionsFree ::fss::tiff_api().OpenOptionsFree
#define TIFFOpenOptionsSetErrorHandlerExtR ::fss::tiff_api().OpenOptionsSetErrorHandlerExtR
#define TIFFOpenOptionsSetMaxSingleMemAlloc ::fss::tiff_api().OpenOptionsSetMaxSingleMemAlloc
#define TIFFOpenOptionsSetWarningHandlerExtR ::fss::tiff_api().OpenOptionsSetWarningHandlerExtR
#define TIFFReadScanline ::fss::tiff_api().ReadScanline
#define TIFFReadTile ::fss::tiff_api().ReadTile
#define TIFFScanlineSize ::fss::tiff_api().ScanlineSize
#define TIFFSetErrorHandler ::fss::tiff_api().SetErrorHandler
#define TIFFSetErrorHandlerExt ::fss::tiff_api().SetErrorHandlerExt
#define TIFFSetField ::fss::tiff_api().SetField
#define TIFFSetWarningHandler ::fss::tiff_api().SetWarningHandler
#define TIFFSetWarningHandlerExt ::fss::tiff_api().SetWarningHandlerExt
#define TIFFTileSize ::fss::tiff_api().TileSize
#define TIFFWriteScanline ::fss::tiff_api().WriteScanline
