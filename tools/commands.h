/* The romkit subcommands, one file each (tools/cmd_*.c). Each returns the process exit code:
 * 0 success, 1 failure (message on stderr as "romkit CMD: ..."), 2 bad usage. */
#ifndef ROMKIT_COMMANDS_H
#define ROMKIT_COMMANDS_H

int cmd_mesh(int argc, char **argv);
int cmd_fom(int argc, char **argv);
int cmd_motions(int argc, char **argv);
int cmd_adaptive(int argc, char **argv);
int cmd_basis(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_build(int argc, char **argv);
int cmd_cubature(int argc, char **argv);
int cmd_plan(int argc, char **argv);
int cmd_run(int argc, char **argv);
int cmd_rom(int argc, char **argv);
int cmd_track(int argc, char **argv);
int cmd_dmd(int argc, char **argv);
int cmd_neural_dmd(int argc, char **argv);
int cmd_control(int argc, char **argv);
int cmd_inspect(int argc, char **argv);
int cmd_export(int argc, char **argv);

/* Shared by the commands: is argv[i] "--help" or "-h". */
int is_help(const char *arg);

#endif
