// Private to the plots (src/io/plot_*.cpp): the PLplot functions they call, taken from the
// library loaded at the first picture (plplot_api.cpp), so that a run that draws nothing never
// maps PLplot. After this header, PLplot's names (plcol0, plline, ...) call the loaded functions.
#pragma once

#include <plplot/plplot.h>

namespace fss::plotting {

// Every PLplot function the plots call, as X(member, symbol).
// clang-format off
#define FSS_PLPLOT_FUNCTIONS(X)                                                                 \
  X(adv, c_pladv) X(box, c_plbox) X(col0, c_plcol0) X(end1, c_plend1) X(erry, c_plerry)         \
  X(fill, c_plfill) X(gDevs, plgDevs) X(gstrm, c_plgstrm) X(gvpd, c_plgvpd) X(gvpw, c_plgvpw)   \
  X(init, c_plinit) X(join, c_pljoin) X(line, c_plline) X(lsty, c_pllsty)                       \
  X(mkstrm, c_plmkstrm) X(mtex, c_plmtex) X(poin, c_plpoin) X(ptex, c_plptex)                   \
  X(sabort, plsabort) X(schr, c_plschr) X(scmap0n, c_plscmap0n) X(scol0, c_plscol0)             \
  X(sdev, c_plsdev) X(sexit, plsexit) X(smema, c_plsmema) X(spause, c_plspause)                 \
  X(sstrm, c_plsstrm) X(ssym, c_plssym) X(vpor, c_plvpor) X(width, c_plwidth)                   \
  X(wind, c_plwind)
// clang-format on

// One pointer a function, with PLplot's own signature.
struct PlplotApi {
// A declaration: its arguments are names, which parentheses would break.
// NOLINTNEXTLINE(bugprone-macro-parentheses)
#define FSS_PLPLOT_MEMBER(member, symbol) decltype(&::symbol) member = nullptr;
  FSS_PLPLOT_FUNCTIONS(FSS_PLPLOT_MEMBER)
#undef FSS_PLPLOT_MEMBER
};

// PLplot's functions, the library loaded at the first call; an fss::Error (runtime) when it or
// one of its functions is missing.
const PlplotApi& plplot_api();

}  // namespace fss::plotting

#undef pladv
#define pladv ::fss::plotting::plplot_api().adv
#undef plbox
#define plbox ::fss::plotting::plplot_api().box
#undef plcol0
#define plcol0 ::fss::plotting::plplot_api().col0
#undef plend1
#define plend1 ::fss::plotting::plplot_api().end1
#undef plerry
#define plerry ::fss::plotting::plplot_api().erry
#undef plfill
#define plfill ::fss::plotting::plplot_api().fill
#define plgDevs ::fss::plotting::plplot_api().gDevs
#undef plgstrm
#define plgstrm ::fss::plotting::plplot_api().gstrm
#undef plgvpd
#define plgvpd ::fss::plotting::plplot_api().gvpd
#undef plgvpw
#define plgvpw ::fss::plotting::plplot_api().gvpw
#undef plinit
#define plinit ::fss::plotting::plplot_api().init
#undef pljoin
#define pljoin ::fss::plotting::plplot_api().join
#undef plline
#define plline ::fss::plotting::plplot_api().line
#undef pllsty
#define pllsty ::fss::plotting::plplot_api().lsty
#undef plmkstrm
#define plmkstrm ::fss::plotting::plplot_api().mkstrm
#undef plmtex
#define plmtex ::fss::plotting::plplot_api().mtex
#undef plpoin
#define plpoin ::fss::plotting::plplot_api().poin
#undef plptex
#define plptex ::fss::plotting::plplot_api().ptex
#define plsabort ::fss::plotting::plplot_api().sabort
#undef plschr
#define plschr ::fss::plotting::plplot_api().schr
#undef plscmap0n
#define plscmap0n ::fss::plotting::plplot_api().scmap0n
#undef plscol0
#define plscol0 ::fss::plotting::plplot_api().scol0
#undef plsdev
#define plsdev ::fss::plotting::plplot_api().sdev
#define plsexit ::fss::plotting::plplot_api().sexit
#undef plsmema
#define plsmema ::fss::plotting::plplot_api().smema
#undef plspause
#define plspause ::fss::plotting::plplot_api().spause
#undef plsstrm
#define plsstrm ::fss::plotting::plplot_api().sstrm
#undef plssym
#define plssym ::fss::plotting::plplot_api().ssym
#undef plvpor
#define plvpor ::fss::plotting::plplot_api().vpor
#undef plwidth
#define plwidth ::fss::plotting::plplot_api().width
#undef plwind
#define plwind ::fss::plotting::plplot_api().wind
