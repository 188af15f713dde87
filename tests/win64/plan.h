/* What the FMI 2.0 and the FMI 3.0 master of tests/win64 share: the library loaded with LoadLibrary (Windows)
 * or dlopen (elsewhere) and its functions found by name, the plan's conventions (hex-encoded strings, Reals
 * as the 16 hex digits of their IEEE 754 bits, the `L` and `R` output lines), the FMU-state commands (whose
 * functions have the same signatures in both versions, under other names) and the loop over the plan.
 *
 * The plan has one call per line, `<instance slot 0-3> <command> <arguments>`; for each line the master
 * prints the lines the FMU logged during the call (`L <status> <category hex> <message hex>`), then
 * `R <line> <status>` and the values the call returned; status NO_FILE means a file the plan names could
 * not be read or written, -1 (which ends the run) an unknown command. A crash ends the process: the last
 * `R` line tells which call it was.
 *
 * State commands: get_state S   set_state S   free_state S   serialize S FILE   deserialize S FILE
 *   flip FILE OFFSET (the file's byte at OFFSET xor-ed with 0x55: a corrupted state blob)
 */
#ifndef WHEELRAIL_PLAN_H
#define WHEELRAIL_PLAN_H

#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _WIN32
#include <windows.h>
#else
#include <dlfcn.h>
#endif

typedef void *Comp;
typedef void *State;
typedef int Status;

#define SLOTS 4
/* The status printed when a file the plan names cannot be read or written (not an FMI status). */
#define NO_FILE 8
/* What run_state_command returns for a command that is not a state command. */
#define NOT_A_STATE_COMMAND -2
#define MAX_TOKENS 256
#define MAX_VALUES 128

static Comp instances[SLOTS];
static State states[SLOTS];
static void *library;

static void *symbol(const char *name) {
#ifdef _WIN32
    void *f = (void *)GetProcAddress((HMODULE)library, name);
#else
    void *f = dlsym(library, name);
#endif
    if (!f) {
        printf("E missing symbol %s\n", name);
        exit(2);
    }
    return f;
}
#define FN(type, name) ((type)symbol(name))

static void hex_out(const unsigned char *s, size_t n) {
    if (!n) {
        fputs(".", stdout);
        return;
    }
    for (size_t i = 0; i < n; i++) printf("%02x", s[i]);
}

/* The `L` line of one logged message. */
static void log_line(int status, const char *category, const char *message) {
    printf("L %d ", status);
    hex_out((const unsigned char *)(category ? category : ""), category ? strlen(category) : 0);
    putchar(' ');
    hex_out((const unsigned char *)message, strlen(message));
    putchar('\n');
}

/* A hex-encoded string argument: "-" null, "." empty; the result lives until the next line. */
static char strings[MAX_TOKENS][4096];
static const char *str_arg(const char *tok, int k) {
    if (!strcmp(tok, "-")) return NULL;
    if (!strcmp(tok, ".")) return "";
    size_t n = strlen(tok) / 2;
    if (n >= sizeof strings[0]) n = sizeof strings[0] - 1;
    for (size_t i = 0; i < n; i++) {
        unsigned v;
        sscanf(tok + 2 * i, "%2x", &v);
        strings[k][i] = (char)v;
    }
    strings[k][n] = 0;
    return strings[k];
}
static double real_arg(const char *tok) {
    uint64_t bits = strtoull(tok, NULL, 16);
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}
/* Appends " <bits>" of a Real to out (room bytes left); returns the characters written. */
static size_t put_real(char *out, size_t room, double x) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    return (size_t)snprintf(out, room, " %016" PRIx64, bits);
}
/* Appends " <hex>" of a string to out ("." for null or empty); returns the characters written. */
static size_t put_string(char *out, size_t room, const char *s) {
    size_t used = (size_t)snprintf(out, room, " ");
    for (const char *p = s ? s : ""; *p && used + 3 < room; p++)
        used += (size_t)snprintf(out + used, room - used, "%02x", (unsigned char)*p);
    if (!s || !*s) used += (size_t)snprintf(out + used, room - used, ".");
    return used;
}

static unsigned char *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *bytes = malloc(n > 0 ? (size_t)n : 1);
    *size = fread(bytes, 1, (size_t)n, f);
    fclose(f);
    return bytes;
}
/* Whether the file could be written. */
static int write_file(const char *path, const unsigned char *bytes, size_t size) {
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fwrite(bytes, 1, size, f);
    fclose(f);
    return 1;
}

/* The names of a version's FMU-state functions. */
typedef struct {
    const char *get, *set, *free, *size, *serialize, *deserialize;
} StateFunctions;

/* Runs a state command on instance c; NOT_A_STATE_COMMAND for any other command. */
static Status run_state_command(const StateFunctions *fs, Comp c, const char *cmd, char **t, char *out,
                                size_t out_size) {
    if (!strcmp(cmd, "get_state") || !strcmp(cmd, "set_state") || !strcmp(cmd, "free_state")) {
        int k = atoi(t[1]) % SLOTS;
        if (!strcmp(cmd, "get_state")) return FN(Status(*)(Comp, State *), fs->get)(c, &states[k]);
        if (!strcmp(cmd, "set_state")) return FN(Status(*)(Comp, State), fs->set)(c, states[k]);
        Status s = FN(Status(*)(Comp, State *), fs->free)(c, &states[k]);
        states[k] = NULL;
        return s;
    }
    if (!strcmp(cmd, "serialize")) {
        int k = atoi(t[1]) % SLOTS;
        size_t size = 0;
        Status s = FN(Status(*)(Comp, State, size_t *), fs->size)(c, states[k], &size);
        if (s > 1) return s;
        unsigned char *bytes = malloc(size ? size : 1);
        s = FN(Status(*)(Comp, State, unsigned char *, size_t), fs->serialize)(c, states[k], bytes, size);
        int written = s <= 1 && write_file(t[2], bytes, size);
        free(bytes);
        snprintf(out, out_size, " %zu", size);
        return written || s > 1 ? s : NO_FILE;
    }
    if (!strcmp(cmd, "deserialize")) {
        int k = atoi(t[1]) % SLOTS;
        size_t size = 0;
        unsigned char *bytes = read_file(t[2], &size);
        if (!bytes) return NO_FILE;
        Status s = FN(Status(*)(Comp, const unsigned char *, size_t, State *), fs->deserialize)(c, bytes, size,
                                                                                               &states[k]);
        free(bytes);
        return s;
    }
    if (!strcmp(cmd, "flip")) {
        size_t size = 0;
        unsigned char *bytes = read_file(t[1], &size);
        size_t at = (size_t)strtoul(t[2], NULL, 10);
        if (!bytes || at >= size) return NO_FILE;
        bytes[at] ^= 0x55;
        int written = write_file(t[1], bytes, size);
        free(bytes);
        return written ? 0 : NO_FILE;
    }
    return NOT_A_STATE_COMMAND;
}

/* Runs one plan line (its n tokens after the slot); returns the status, printing returned values to out. */
typedef Status (*LineRunner)(int slot, int n, char **t, char *out, size_t out_size);

/* The master's main: `NAME LIBRARY PLAN`, the library loaded, each line of the plan run by run_line. */
static int run_plan(int argc, char **argv, LineRunner run_line) {
    static char line[65536], out[65536];
    char *tokens[MAX_TOKENS];
    if (argc != 3) {
        fprintf(stderr, "usage: %s LIBRARY PLAN\n", argv[0]);
        return 2;
    }
    setvbuf(stdout, NULL, _IOFBF, 1 << 16);
#ifdef _WIN32
    library = (void *)LoadLibraryA(argv[1]);
    if (!library) {
        printf("E LoadLibrary %s failed: error %lu\n", argv[1], (unsigned long)GetLastError());
        return 2;
    }
#else
    library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        printf("E dlopen %s failed: %s\n", argv[1], dlerror());
        return 2;
    }
#endif
    FILE *plan = fopen(argv[2], "r");
    if (!plan) {
        printf("E cannot read the plan %s\n", argv[2]);
        return 2;
    }
    for (int number = 1; fgets(line, sizeof line, plan); number++) {
        int n = 0;
        for (char *tok = strtok(line, " \r\n"); tok && n < MAX_TOKENS; tok = strtok(NULL, " \r\n"))
            tokens[n++] = tok;
        if (n < 2 || tokens[0][0] == '#') continue;
        int slot = atoi(tokens[0]) % SLOTS;
        Status s = run_line(slot, n - 1, tokens + 1, out, sizeof out);
        printf("R %d %d%s\n", number, s, out);
        if (s == -1) {
            printf("E plan line %d: bad command or arguments\n", number);
            return 2;
        }
    }
    fclose(plan);
    fflush(stdout);
    return 0;
}

#endif
