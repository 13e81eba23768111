/* help.c -- the usage text of every command: `mpgm help` (the overview),
 * `mpgm help COMMAND`, `mpgm COMMAND --help` and `-h`. main.c answers them
 * before a command reads its own arguments, so a command's parser needs no
 * help option of its own. One text per command: what it does, its usage
 * and every option, with a pointer to the document that says more. */
#include "help.h"

#include <string.h>

typedef struct help_text {
  const char *name, *text;
} help_text;

static const help_text TEXTS[] = {
    {"run",
     "usage: mpgm run SCENE [--set KEY=VALUE ...] [--out DIR] [--force] [--progress | --quiet]\n"
     "       mpgm run --restart DIR [SCENE] [--set KEY=VALUE ...] [--progress | --quiet]\n"
     "\n"
     "Run a scene; its results go to DIR (default: the scene's output.dir).\n"
     "\n"
     "  --set KEY=VALUE  override any scene value by dotted path, e.g. --set mesh.h=0.125\n"
     "  --out DIR        the results folder\n"
     "  --force          replace the run of another scene that DIR holds (without it\n"
     "                   such a run is refused, exit 2; the same scene runs again in place)\n"
     "  --restart DIR    continue the interrupted run in DIR from its last checkpoint\n"
     "                   (output.checkpoint_every), with the scene it was started with\n"
     "  --progress       a progress line: rewritten in place on a terminal, else a plain\n"
     "                   line every 5 s and one at the end (the default)\n"
     "  --quiet          no progress line\n"
     "  --time-split     log the time split of every step (benchmarks)\n"
     "\n"
     "The run ends with one summary line on stdout: status, steps, step cuts, the\n"
     "case's main metrics, wall time and the results folder (docs/scene-format.md,\n"
     "\"The console\").\n"
     "exit codes: 0 success, 1 simulation failed, 2 bad input, 3 I/O error,\n"
     "128 + N stopped by signal N\n"},
    {"check",
     "usage: mpgm check SCENE [--set KEY=VALUE ...]\n"
     "\n"
     "Validate a scene; print the resolved scene, its effects and the memory the run\n"
     "needs; run nothing.\n"
     "\n"
     "  --set KEY=VALUE  override any scene value by dotted path, e.g. --set mesh.h=0.125\n"
     "\n"
     "exit codes: 0 valid, 2 bad input (FILE: json.path: expected ..., found ...)\n"},
    {"material",
     "usage: mpgm material FILE.json [--out FILE.csv]\n"
     "\n"
     "Drive one material along a deformation path (docs/material-driver.md).\n"
     "\n"
     "  --out FILE.csv   the CSV (default: FILE's name with .csv, in the current folder)\n"},
    {"study",
     "usage: mpgm study STUDY.json [--jobs N] [--out DIR] [--no-plot] [--rerun-failed] [--dry-run]\n"
     "\n"
     "Run a scene over axes of --set values, resumably; study.csv and plots\n"
     "(docs/studies.md).\n"
     "\n"
     "  --jobs N         runs at a time (default: the file's \"jobs\", else 2)\n"
     "  --out DIR        the study folder (default: the file's \"out\")\n"
     "  --no-plot        no plots after the runs\n"
     "  --rerun-failed   run the failed runs of an earlier session again\n"
     "  --dry-run        count the runs to do and those complete; run nothing\n"},
    {"plot",
     "usage: mpgm plot STUDY.csv [--metric NAME] [--x KEY] [--y METRIC] [--series KEY,...]\n"
     "                 [--xscale linear|log] [--yscale linear|log|signed] [--out DIR] [--title TEXT]\n"
     "\n"
     "Draw a study.csv with gnuplot: the error against mesh size and against wall\n"
     "time, or any column against any other (docs/studies.md).\n"
     "\n"
     "  --metric NAME    the error drawn (default: the study's metric)\n"
     "  --x KEY          the column along x (default mesh.h)\n"
     "  --y METRIC       the column along y\n"
     "  --series KEY,... one curve per value of these columns\n"
     "  --xscale S       linear or log\n"
     "  --yscale S       linear, log or signed\n"
     "  --out DIR        where the pictures go (default: STUDY.csv's folder)\n"
     "  --title TEXT     the plots' title\n"},
    {"render",
     "usage: mpgm render RUN_DIR [--field NAME] [--time T,...|last] [--out DIR] [--sheet FILE.png]\n"
     "                   [--layout RxC] [--size WxH] [--range MIN:MAX] [--xrange A:B] [--yrange A:B]\n"
     "                   [--radius R] [--title TEXT] [--view AB]\n"
     "\n"
     "Draw a run's material points coloured by a field at given times\n"
     "(docs/studies.md); a 3-D run projected, seen along the third axis.\n"
     "\n"
     "  --field NAME     the field (default displacement)\n"
     "  --time T,...     the times drawn, or last (the default)\n"
     "  --out DIR        where the pictures go (default RUN_DIR/render)\n"
     "  --sheet FILE.png all the times as panels of one picture\n"
     "  --layout RxC     the sheet's rows and columns\n"
     "  --size WxH       the picture's size in pixels\n"
     "  --range MIN:MAX  the colour range\n"
     "  --xrange A:B     the x range drawn\n"
     "  --yrange A:B     the y range drawn\n"
     "  --radius R       the points' radius\n"
     "  --title TEXT     the picture's title\n"
     "  --view AB        3-D: axis A across, B up, seen from +the third (default:\n"
     "                   x across, gravity's axis up)\n"},
    {"bench-solvers",
     "usage: mpgm bench-solvers DIR [--repeat N] [--out FILE.csv] [--only NAME,...]\n"
     "                          [--tol X] [--restart M] [--max-iterations N]\n"
     "\n"
     "Time every linear solver backend on the systems a run wrote with\n"
     "--set output.matrices=STEP (DIR: the run folder or its matrices/); a CSV and a\n"
     "Markdown table on stdout (docs/scene-format.md, \"Command line\").\n"
     "\n"
     "  --repeat N          best of N (default 3)\n"
     "  --out FILE.csv      the CSV (default DIR/matrices/bench_solvers.csv)\n"
     "  --only NAME,...     these backends (NAME, or NAME:PRESET as petsc:cg-gamg)\n"
     "  --tol X             the iterative backends' tolerance (solver.linear_tol)\n"
     "  --restart M         their restart (solver.linear_restart)\n"
     "  --max-iterations N  their iteration limit (solver.linear_max_iterations)\n"},
    {"help",
     "usage: mpgm help [COMMAND]\n"
     "       mpgm COMMAND --help | -h\n"
     "\n"
     "Print the overview of the commands, or COMMAND's usage and options.\n"},
    {"version",
     "usage: mpgm version\n"
     "\n"
     "Print mpgm's version (what summary.json and a checkpoint record).\n"},
};

void mpgm_help_overview(FILE *f) {
  fprintf(f,
          "usage: mpgm run SCENE [--set KEY=VALUE ...] [--out DIR] [--force] [--progress | --quiet]\n"
          "       mpgm run --restart DIR [SCENE] [--set KEY=VALUE ...] [--progress | --quiet]\n"
          "       mpgm check SCENE [--set KEY=VALUE ...]\n"
          "       mpgm material FILE.json [--out FILE.csv]\n"
          "       mpgm study STUDY.json [--jobs N] [--out DIR] [--no-plot] [--rerun-failed] [--dry-run]\n"
          "       mpgm plot STUDY.csv [--metric NAME] [--x KEY] [--y METRIC] [--series KEY,...] ...\n"
          "       mpgm render RUN_DIR [--field NAME] [--time T,...|last] [--out DIR] ...\n"
          "       mpgm bench-solvers DIR [--repeat N] [--out FILE.csv] [--only NAME,...] ...\n"
          "       mpgm help [COMMAND] | version\n"
          "\n"
          "  run       run a scene; results go to DIR (default: the scene's output.dir)\n"
          "  check     validate a scene, print the resolved scene and its effects; run nothing\n"
          "  material  drive one material along a deformation path (docs/material-driver.md)\n"
          "  study     run a scene over axes of --set values, resumably (docs/studies.md)\n"
          "  plot      draw a study.csv\n"
          "  render    draw a run's material points coloured by a field at given times\n"
          "  bench-solvers  time every linear solver backend on the systems a run wrote\n"
          "\n"
          "mpgm help COMMAND, or mpgm COMMAND --help: the command's options.\n"
          "exit codes: 0 success, 1 simulation failed, 2 bad input, 3 I/O error\n"
          "scene format: docs/scene-format.md\n");
}

int mpgm_help_command(FILE *f, const char *command) {
  for (size_t i = 0; i < sizeof TEXTS / sizeof *TEXTS; i++)
    if (strcmp(command, TEXTS[i].name) == 0) {
      fputs(TEXTS[i].text, f);
      return 0;
    }
  return -1;
}

int mpgm_help_asked(int argc, char **argv) {
  for (int i = 2; i < argc; i++)
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) return 1;
  return 0;
}
