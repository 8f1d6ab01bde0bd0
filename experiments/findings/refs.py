"""The literature the findings cite, by key: every number not computed here has one."""

REFS = {
    "cross2009": 'R. Cross, "Mechanics of swinging a bat", Am. J. Phys. 77, 36 (2009): the R161 '
    "data (0.871 kg, 0.84 m, COM 0.56 m, J_cm 0.039 kg m^2), used by the paper.",
    "cross1998": 'R. Cross, "The sweet spot of a baseball bat", Am. J. Phys. 66, 772 (1998): '
    "defines the sweet spot by the bat's vibration node and the centre of "
    "percussion.",
    "crossnotes": "R. Cross, notes on the physics of baseball and softball bats "
    "(physics.usyd.edu.au/~cross): the sweet spot of a major-league bat about "
    "17 cm from the barrel end.",
    "russell": 'D. A. Russell, "The sweet spot of a hollow baseball or softball bat", Kettering '
    "University (2004) (the paper's ref. [2]): a region about 5-7 in (12.7-17.8 cm) "
    "from the barrel end.",
    "nathan2000": 'A. M. Nathan, "Dynamics of the baseball-bat collision", Am. J. Phys. 68, 979 '
    "(2000): a flexible-bat model; where a batter feels the sweet spot is set by "
    "the bat's vibrations, which a rigid bat does not have; ball COR about 0.5 at "
    "40-60 m/s, contact 0.6-1 ms.",
    "russellmodes": 'D. A. Russell, "Vibrational modes of a baseball bat", Physics and '
    "Acoustics of Baseball & Softball Bats (acs.psu.edu/drussell/bats, 2003): "
    "the first bending mode of a bat about 170 Hz, its barrel node 5-7 in from "
    "the barrel end.",
    "woodhandbook": "USDA Forest Products Laboratory, Wood Handbook, FPL-GTR-190 (2010), "
    "tables 5-1 and 5-3a: white ash E_L = 12.0 GPa at 12% moisture, specific "
    "gravity 0.60 (oven-dry mass over volume at 12% moisture; 0.55 is its basic specific gravity, "
    "over green volume, not a density), G_LR/E_L = 0.080; table 5-6: E's coefficient of "
    "variation between pieces 22%.",
    "crossbower": 'R. Cross and R. Bower, "Effects of swing-weight on swing speed and racket '
    'power", J. Sports Sci. 24, 23 (2006): swing speed ~ I^-n, n = 0.27 (0.25 '
    "for softball bats).",
    "nathan2011": 'A. M. Nathan, L. V. Smith, W. L. Faber, D. A. Russell, "Corked bats, juiced '
    'balls, and humidors: the physics of cheating in baseball", Am. J. Phys. 79, '
    "575 (2011): collision efficiency measured with a ball cannon and a stationary "
    "bat, q = 0.214 (solid) and 0.193 (corked); swing speed argued from swing-weight "
    "scaling; batted distance not measured.",
    "nathan2011se": "A. M. Nathan, J. J. Crisco, R. M. Greenwald, D. A. Russell, L. V. Smith, "
    '"A comparative study of baseball bat performance", Sports Eng. 13, 153 '
    "(2011): in measured swings the bat's instantaneous axis of rotation at "
    "impact lies near the knob.",
    "crisco2002": 'J. J. Crisco, R. M. Greenwald, J. D. Blume, L. H. Penna, "Batting '
    'performance of wood and metal baseball bats", Med. Sci. Sports Exerc. 34, '
    "1675 (2002): the sweet spot lies the same distance from the tip on wood and "
    "metal bats; metal's higher batted-ball speeds come from faster swings and a "
    "livelier (more elastic) collision.",
    "ncaa": "NCAA baseball bat standard (BBCOR, 2011): a ball-bat coefficient of restitution of "
    "at most 0.50 (slightly above the best wood bats), measured with a ball fired at "
    "136 mph (60.8 m/s) at a stationary bat, kept beside the length-to-weight rule (at "
    "most -3) and the moment-of-inertia rule (measured about a point 6 in from the "
    "knob).",
    "mlbcor": "MLB's baseball specification: a COR of 0.546 +- 0.032 (0.514-0.578) when fired "
    "at 85 ft/s (58 mph, 25.9 m/s) at a northern white ash wall, as reported with "
    "the tests of [msnbc2003].",
    "msnbc2003": "D. Ropeik, \"Squeezing the 'juice' out of baseballs\", msnbc.com (2003): the "
    "UMass Lowell Baseball Research Center (J. Sherwood) fired MLB balls at an ash "
    "wall at 85 ft/s; the sample averaged a COR of 0.55.",
    "johnson1985": "K. L. Johnson, Contact Mechanics, Cambridge University Press (1985), "
    "ch. 11: in an elastic-plastic impact e falls as v^-1/4.",
    "rules": "Official Baseball Rules (MLB): ball 5-5.25 oz, 9-9.25 in around (3.01); bats of "
    "one piece of solid wood, barrel at most 2.61 in (3.02), a wood-only rule, not a "
    "BBCOR one; pitching rubber 60 ft 6 in (18.44 m) from home plate.",
    "shenoy2001": "M. M. Shenoy, L. V. Smith, J. T. Axtell, Composite Structures 52, 397 (2001), "
    '"Performance assessment of wood, metal and composite baseball bats" '
    "(abstract): the ball's COR depends on the impact speed.",
    "sawicki2003": "G. S. Sawicki, M. Hubbard, W. J. Stronge, Am. J. Phys. 71, 1152 (2003), "
    '"How to hit home runs" (abstract): undercut and upward swing angle set for '
    "the longest carry, e falling with closing speed; post-impact conditions "
    "independent of ball-bat friction; a curveball carries farther than a fastball.",
    "popmech2009": "D. Coburn, Popular Mechanics, 18 Dec 2009: Hubbard's 94 mph fastball leaves "
    "the bat 3 mph faster than a 78 mph curveball but flies 442 ft to its 455 ft.",
    "crossnathan2006": "R. Cross, A. M. Nathan, Am. J. Phys. 74, 896 (2006): a curveball can be "
    "hit with more backspin than a fastball, by less than rigid rolling gives.",
    "kensrud2017": "J. R. Kensrud, A. M. Nathan, L. V. Smith, Am. J. Phys. 85, 503 (2017): the "
    "ball grips the bat, leaving with up to 40% more spin than rigid rolling.",
    "nathan2012": 'A. M. Nathan et al., "Spin of a batted baseball", Procedia Eng. 34, 182 '
    "(2012): the scattered spin is nearly independent of the incident spin.",
    "statcast": "Statcast: 2016 four-seam fastballs 2,264 rpm (MLB.com, 3 Jan 2017); 2024 "
    "curveballs 2,569 rpm at 79.4 mph (statcast_2024_grouped.csv, TJStats).",
    "nathancalc": "A. M. Nathan's trajectory calculator (drag and lift fitted to Statcast fly "
    "balls) and Am. J. Phys. 76, 119 (2008), as in `analytic.flight`.",
    "nathancork": 'A. M. Nathan, "What about filling the cavity with superballs?", corked-bat '
    "notes (2003, reproduced at xbats.com): measured with D. A. Russell and L. V. Smith, a "
    "34 in, 30.5 oz wood bat drilled 1 in across and 10 in deep weighed 27.6 oz (2.9 oz, "
    "82 g, removed).",
    "adair": "R. K. Adair, The Physics of Baseball, 3rd ed. (2002), ch. 2: C_D uncertain by 10%.",
    "mlbrelease": "MLB.com, 3 Jun 2023: release 6.4 ft before the rubber, 16.5 m from the plate.",
}
