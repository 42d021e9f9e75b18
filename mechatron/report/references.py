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
                "determining tool forces.",
    "ISO 6336-3": "ISO 6336-3:2019, Calculation of load capacity of spur and helical gears — Part 3: Calculation "
                  "of tooth bending strength (the life factor Y_NT of case-hardened teeth, 2.5 at 10³ and 1 at "
                  "3·10⁶ load cycles: the slope of the gearbox peak-torque derating above its cycle rating).",
    "ISO 10567": "ISO 10567:2007, Earth-moving machinery — Hydraulic excavators — Lift capacity (the lift point, the "
                 "tipping lines over the front and over the side, and the rated lift capacity: the smaller of 75 % "
                 "of the tipping load and 87 % of the hydraulic lift capacity).",
    "Saltelli": 'A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola, "Variance based sensitivity '
                'analysis of model output. Design and estimator for the total sensitivity index", Computer Physics '
                "Communications 181(2), 2010: the sampling scheme (matrices A, B and A_B⁽ⁱ⁾) and the first-order "
                "estimator of Sobol indices.",
    "Jansen": 'M. J. W. Jansen, "Analysis of variance designs for model output", Computer Physics Communications '
              "117(1–2), 1999: the estimator of the total Sobol index.",
    "Pinocchio": "J. Carpentier et al., The Pinocchio C++ library, IEEE/SICE SII 2019: RNEA, ABA, CRBA and the "
                 "Lie-group operations (`integrate`, `difference`) every computation of mechatron rests on.",
    "vdStraete": 'H. J. van de Straete, P. Degezelle, J. De Schutter, R. J. M. Belmans, "Servo motor selection '
                 'criterion for mechatronic applications", IEEE/ASME Transactions on Mechatronics 3(1), 1998: the '
                 "ratio band within which a motor stays within its rating.",
    "Giberti": 'H. Giberti, S. Cinquemani, G. Legnani, "Effects of transmission mechanical characteristics on the '
               'choice of a motor-reducer", Mechatronics 20(5), 2010: motor–gearbox choice with the transmission\'s '
               "inertia and efficiency.",
    "Vendor sizing": "The configuration and sizing manuals of servo-drive and gearbox makers (Siemens "
                     "SINAMICS/SIMOTICS configuration manuals; Neugart and Wittenstein gearbox selection guides): "
                     "the S1 torque at the mean speed, the speed-weighted cubic mean torque of a gearbox, the "
                     "emergency-stop torque check; and the selection sections of ball-screw and hydraulic-cylinder "
                     "catalogs (THK and HIWIN ball screws, Bosch Rexroth cylinders): the critical speed and "
                     "buckling load of a screw shaft by its end fixing (80 % and 50 % allowed), the buckling length "
                     "K·L of a cylinder by its mountings (Euler's four cases).",
}
