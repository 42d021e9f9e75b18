"""The sources mechatron cites, by key: the table of ``docs/references.md``, shipped with the package so that a
report can resolve ``[Egorov, 4.63]`` to the full reference (the text is that page's, Markdown emphasis included)."""

from __future__ import annotations

#: Key → full reference (Markdown: ``*title*`` in italics, ```code```), in the order of docs/references.md.
REFERENCES: dict[str, str] = {
    "Egorov": "O. D. Egorov, *Прикладная механика мехатронных устройств* (Applied Mechanics of Mechatronic "
              'Devices), textbook. Moscow: MSTU "STANKIN", 2013, 229 pp. ISBN 978-5-7028-0744-7. Chapters: 2 '
              "mechatronic modules and catalogs, 3 structure, 4 kinematics and the transmission ratio, 5 forces, 6 "
              "the reduced (one-mass) dynamic model, 7 friction, wear, life and efficiency, 8 accuracy.",
    "Bucket": "*Анализ шестизвенного механизма для привода рабочих органов строительных и дорожных машин* (Analysis "
              "of a six-link mechanism driving the working bodies of construction and road machines): synthesis of "
              "the geometry and kinematic analysis of the six-link cylinder–rocker–link–bucket mechanism, journal "
              "paper.",
    "Shovel": "*正铲液压挖掘机工作装置设计* (Design of the working device of a front-shovel hydraulic excavator): a "
              "mechanism-design course assignment with its worked report: first sizing of the links, lever and "
              "cylinder synthesis, special positions and working range.",
    "Mikhailov": "I. V. Mikhailov, *Математическая модель движения грейфера* (Mathematical model of grab motion), "
                 "Astrakhan State Technical University, 2006: the half grab scooping along a parabola, with "
                 "Lagrange multipliers.",
    "ShiLiang": "Shi Jinfa, Liang Xichang, *双缸液动平面七杆机构输出杆件的速度分析* (The velocity analysis of the "
                "output link in the plane seven-link mechanism driven by two hydraulic cylinders), State Key "
                "Laboratory of Mechanical Transmission, Chongqing University.",
    "Biagiotti": "L. Biagiotti, C. Melchiorri, *Trajectory Planning for Automatic Machines and Robots*, Springer, "
                 "2008 (the double-S profile, section 3.4).",
    "ISO 286-1": "ISO 286-1:2010, Geometrical product specifications — ISO code system for tolerances on linear "
                 "sizes (the IT grades).",
    "ISO 3320": "ISO 3320:2013, Fluid power systems and components — Cylinder bores and piston rod diameters and "
                "area ratios — Metric series (the bores and rods a catalog's cylinders are checked against).",
    "ISO 3408-5": "ISO 3408-5:2006, Ball screws — Part 5: Static and axial dynamic load ratings and operational "
                  "life (the equivalent axial load, the cubic mean weighted by the revolutions, and the nominal "
                  "life L10 = (C_a/F_m)³·10⁶ revolutions).",
    "ISO 6015": "ISO 6015:2006, Earth-moving machinery — Hydraulic excavators and backhoe loaders — Methods of "
                "determining tool forces. Clauses cited: 3.1 (the tool force, at the bucket lip or cutting edge, not "
                "at the tips of the teeth, with the bucket or arm cylinders operated independently), 3.2 (the arm "
                "cylinder tool force, a moment about the arm pivot), 3.16 (the maximum relief circuit hydraulic "
                "pressure), 3.17–3.19 (the hydraulic, tipping and slipping limit conditions of a measured tool "
                "force), 4.4 (the position giving the maximum force, found by varying the strokes), 4.8.2–4.8.3 (the "
                "arm and bucket cylinder tool forces measured tangential to the arc the bucket lip describes about "
                "the arm pivot and the bucket pivot), 5.2.1–5.2.2 (the rated, calculated, arm and bucket cylinder "
                "tool forces).",
    "Strain wave": "Harmonic Drive catalogs of strain-wave gears (component sets and units of the CSF and CSG "
                   'series), sections "Technical terms, strength and life" and "Selection procedure": the repeated '
                   "peak torque (the limit of the torque during acceleration and deceleration, from the load's "
                   "inertia), the momentary peak torque (a collision or an emergency stop, never in the normal "
                   "operating cycle) and its allowed number of occurrences, the average load torque (the cube root "
                   "of the speed- and time-weighted mean of the cubed torques).",
    "ISO 10567": "ISO 10567:2007, Earth-moving machinery — Hydraulic excavators — Lift capacity (the lift point, the "
                 "tipping load over the front and over the side, and the rated lift capacity: the smaller of 75 % "
                 "of the tipping load and 87 % of the hydraulic lift capacity; where the tipping lines lie is "
                 "mechatron's assumption, not quoted from it).",
    "Caterpillar": 'Caterpillar Performance Handbook (Caterpillar Inc., edition 44, 2014), Tables: "traction '
                   'factors", the usable pull over the weight on tires and on tracks by ground (for tracks: ice '
                   "0.12, dry sand 0.30, concrete 0.45, wet sand 0.50, loose earth 0.60, wet clay loam 0.70, firm "
                   "earth and dry clay loam 0.90).",
    "Saltelli": 'A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola, "Variance based sensitivity '
                'analysis of model output. Design and estimator for the total sensitivity index", Computer Physics '
                "Communications 181(2), 2010: the sampling scheme (matrices A, B and A_B⁽ⁱ⁾) and the first-order "
                "estimator of Sobol indices.",
    "Jansen": 'M. J. W. Jansen, "Analysis of variance designs for model output", Computer Physics Communications '
              "117(1–2), 1999: the estimator of the total Sobol index.",
    "Ishigami": 'T. Ishigami, T. Homma, "An importance quantification technique in uncertainty analysis for computer '
                "models\", Proceedings of ISUMA '90, the First International Symposium on Uncertainty Modeling and "
                "Analysis, 1990: the test function f = sin x1 + a sin² x2 + b x3⁴ sin x1 of three uniforms on [−π, π], "
                "whose Sobol indices have closed forms (the tests of the Sobol estimators).",
    "Chase": 'K. W. Chase, W. H. Greenwood, B. G. Loosli, L. F. Hauglund, "Least cost tolerance allocation for '
             'mechanical assemblies with automated process selection", Manufacturing Review 3(1), 1990, pp. 49–59: '
             'the cost–tolerance curves of processes, among them the reciprocal power model C = A + B/T^k; the '
             'closed-form least-cost allocation by Lagrange multipliers for a worst-case and for an RSS limit on '
             "the assembly's tolerance stack (the tolerances in proportion to the cost coefficients and "
             'sensitivities); and the selection of one process per dimension from its cost–tolerance table as a '
             "discrete optimisation, by exhaustive search and faster searches compared with it. mechatron's limit "
             "is the positioning error of a point at every pose with the exact sensitivities as the stack's "
             'coefficients (ours).',
    "Pinocchio": "J. Carpentier et al., The Pinocchio C++ library, IEEE/SICE SII 2019: RNEA, ABA, CRBA and the "
                 "Lie-group operations (`integrate`, `difference`) every computation of mechatron rests on.",
    "vdStraete": 'H. J. van de Straete, P. Degezelle, J. De Schutter, R. J. M. Belmans, "Servo motor selection '
                 'criterion for mechatronic applications", IEEE/ASME Transactions on Mechatronics 3(1), 1998: the '
                 "ratio band within which a motor stays within its rating.",
    "Giberti": 'H. Giberti, S. Cinquemani, G. Legnani, "Effects of transmission mechanical characteristics on the '
               'choice of a motor-reducer", Mechatronics 20(5), 2010: motor–gearbox choice with the transmission\'s '
               "inertia and efficiency.",
    "IEC 60034-1": "IEC 60034-1:2017, Rotating electrical machines — Part 1: Rating and performance. Clauses cited: "
                   "4.2 (the duty types: 4.2.1 S1 continuous running duty, operation at a constant load long enough "
                   "to reach thermal equilibrium; 4.2.2 S2 short-time duty, a constant load for less time than that, "
                   "then a rest de-energised until within 2 K of the coolant; 4.2.3 S3 intermittent periodic duty, "
                   "identical cycles of a constant load and a rest de-energised, the starting current not affecting "
                   "the temperature rise significantly; 4.2.4 S4 the same with a significant starting time; 4.2.5 "
                   "S5 the same with starting and electric braking; 4.2.6 S6 continuous-operation periodic duty, "
                   "identical cycles of a constant load and no-load running, no rest; 4.2.7 S7 the same with "
                   "starting and electric braking, no rest; 4.2.8 S8 constant loads at related speeds, no rest; "
                   "4.2.9 S9 non-periodic load and speed variations within the permissible range, overloads "
                   "included; 4.2.10 S10 discrete constant loads, each to thermal equilibrium), the cyclic duration "
                   "factor of S3 … S6 (the time under load, with starting and electric braking, over the cycle's), "
                   "and clause 6 (the site operating conditions the ratings refer to: an altitude of at most "
                   "1,000 m and ambient air of at most 40 °C).",
    "Magnets": 'Advanced Magnets (Stanford Magnets), "What are temperature coefficients α and β of permanent '
               'magnets?", advancedmagnets.com, technical note: the reversible temperature coefficient α of '
               "remanence, [B_r(T₁) − B_r(T₂)] / (B_r(T₁) (T₁ − T₂)); typically −0.09 … −0.12 %/°C for sintered "
               "NdFeB magnets (N48SH from 20 to 150 °C: −0.119 %/°C) and −0.03 … −0.05 %/°C for sintered SmCo.",
    "Vendor sizing": "The configuration and sizing manuals of servo-drive and gearbox makers (Siemens "
                     "SINAMICS/SIMOTICS configuration manuals; Neugart and Wittenstein gearbox selection guides): "
                     "the S1 torque at the mean speed, the speed-weighted cubic mean torque of a gearbox, the "
                     "emergency-stop torque check, the gearbox's peak (acceleration) torque T2B up to a cycle rate "
                     "(commonly 1,000 cycles per hour) and the shock factor by cycles per hour that multiplies the "
                     "peak torque asked for above it; and the selection sections of ball-screw and hydraulic-cylinder "
                     "catalogs (THK and HIWIN ball screws, Bosch Rexroth cylinders): the critical speed and "
                     "buckling load of a screw shaft by its end fixing (80 % and 50 % allowed), the buckling length "
                     "K·L of a cylinder by its mountings (Euler's four cases).",
    "ISO 22514-2": "ISO 22514-2:2017, Statistical methods in process management — Capability and performance "
                   "— Part 2: Process capability and performance of time-dependent process models (the "
                   "process performance indices Pp = (U − L)/(6σ̂) and Ppk = min(U − μ̂, μ̂ − L)/(3σ̂), and "
                   "the one-sided Ppk of a characteristic with an upper limit only, (U − μ̂)/(3σ̂), σ̂ the "
                   "overall standard deviation of the samples).",
    "Bissell": "A. F. Bissell, \"How reliable is your capability index?\", Journal of the Royal Statistical "
               "Society, Series C (Applied Statistics) 39, 1990, pp. 331–340: the approximate standard error "
               "of the estimated Cpk of normal samples, √(1/(9n) + Cpk²/(2(n − 1))), and the interval Cpk ± "
               "z·that.",
    "Clopper": "C. J. Clopper, E. S. Pearson, \"The use of confidence or fiducial limits illustrated in the "
               "case of the binomial\", Biometrika 26(4), 1934, pp. 404–413: the exact (\"Clopper–Pearson\") "
               "interval of a binomial proportion, written with the beta distribution's quantiles.",
    "Pebay": "P. Pébay, \"Formulas for robust, one-pass parallel computation of covariances and "
             "arbitrary-order statistical moments\", Sandia report SAND2008-6212, 2008: the pairwise update of"
             " the central sums of powers of two sets of samples merged (to the fourth order here).",
    "Hollerbach": "J. M. Hollerbach, C. W. Wampler, \"The calibration index and taxonomy for robot kinematic "
                  "calibration methods\", The International Journal of Robotics Research 15(6), 1996, pp. "
                  "573–591: section 4 (the kinematic parameters and encoder offsets to identify, and why a "
                  "set with redundant parameters is not identifiable), section 5 (identifiability from the "
                  "rank and the singular values of the identification Jacobian, the condition number, "
                  "parameter scaling).",
    "Moré": "J. J. Moré, \"The Levenberg–Marquardt algorithm: implementation and theory\", in G. A. Watson "
            "(ed.), Numerical Analysis, Lecture Notes in Mathematics 630, Springer, 1978, pp. 105–116: the "
            "damped Gauss–Newton step and the scaling of the unknowns by the column norms of the Jacobian.",
}
