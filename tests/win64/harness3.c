/* An FMI 3.0 master that runs a plan of calls against an FMU's shared library, as an importer would: the
 * FMI 3.0 counterpart of harness.c, with the same plan conventions and output lines (plan.h); FMI 3.0's
 * logger is not variadic. Built for Linux (gcc) and for Windows (MinGW-w64, run under Wine) so that
 * tests/win64/test_win64_fmi3.py can compare what the two binaries of the FMU return.
 *
 * Usage: harness3 LIBRARY PLAN
 *
 * Array commands take the number of values apart from the value references, so that wrong lengths can be
 * sent; values are printed as returned when the status is OK or Warning. Commands (see `run_line`):
 *   instantiate_cs NAME TOKEN RESOURCES LOGGING EVENT_MODE   instantiate_me NAME TOKEN RESOURCES LOGGING
 *   free   enter_config   exit_config   enter_init START   exit_init   terminate   reset
 *   set_TYPE NVR VR... NVALUES VALUE...   get_TYPE NVALUES VR...   (TYPE: float64, int32, boolean, string,
 *       uint64; Float64 as bits, strings hex, the others decimal)
 *   do_step T H (prints the four returned flags and the last successful time)
 *   set_time T   enter_ct   enter_event   completed   update_discrete   evaluate_discrete   enter_step
 *   dirder NU U... NK K... NSEED SEED... NSENSITIVITY   adjoint (the same arguments)
 *   get_state S   set_state S   free_state S   serialize S FILE   deserialize S FILE   flip FILE OFFSET
 *   null FUNCTION (the function called with a null instance)   version   process_threads (the threads of
 *   this process: worker threads started and joined)   x87_control_word (this thread's, hex)
 */
#include <stdbool.h>

#include "plan.h"
#ifdef _WIN32
#include <tlhelp32.h>
#else
#include <dirent.h>
#endif

typedef uint32_t VR;
typedef void (*Logger)(void *, Status, const char *, const char *);

/* The logger: FMI 3.0 passes the message formatted. */
static void logger(void *env, Status status, const char *category, const char *message) {
    (void)env;
    log_line(status, category, message ? message : "(null)");
}

static const StateFunctions state_functions = {
    "fmi3GetFMUState",           "fmi3SetFMUState",       "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize", "fmi3SerializeFMUState", "fmi3DeserializeFMUState",
};

/* The functions of the instance alone, by command. */
static const struct {
    const char *command, *function;
} nullary[] = {
    {"enter_config", "fmi3EnterConfigurationMode"},
    {"exit_config", "fmi3ExitConfigurationMode"},
    {"exit_init", "fmi3ExitInitializationMode"},
    {"terminate", "fmi3Terminate"},
    {"reset", "fmi3Reset"},
    {"enter_ct", "fmi3EnterContinuousTimeMode"},
    {"enter_event", "fmi3EnterEventMode"},
    {"evaluate_discrete", "fmi3EvaluateDiscreteStates"},
    {"enter_step", "fmi3EnterStepMode"},
};

/* The value types of the get_TYPE and set_TYPE commands. */
typedef enum { K_FLOAT64, K_INT32, K_BOOLEAN, K_STRING, K_UINT64 } Kind;
static const struct {
    const char *name, *get, *set;
} kinds[] = {
    {"float64", "fmi3GetFloat64", "fmi3SetFloat64"}, {"int32", "fmi3GetInt32", "fmi3SetInt32"},
    {"boolean", "fmi3GetBoolean", "fmi3SetBoolean"}, {"string", "fmi3GetString", "fmi3SetString"},
    {"uint64", "fmi3GetUInt64", "fmi3SetUInt64"},
};
/* Values of any kind (a string is its pointer). */
typedef union {
    double f;
    int32_t i;
    bool b;
    const char *s;
    uint64_t u;
} Value;
typedef Status (*FArray)(Comp, const VR *, size_t, void *, size_t);

/* The kind of a get_TYPE / set_TYPE command (its TYPE after the prefix of `prefix_length`), or -1. */
static int kind_of(const char *cmd, size_t prefix_length) {
    for (int k = 0; k < (int)(sizeof kinds / sizeof kinds[0]); k++)
        if (!strcmp(cmd + prefix_length, kinds[k].name)) return k;
    return -1;
}

/* Copies values of `kind` into the array `to` of that C type. */
static void *packed(Kind kind, const Value *v, size_t n, void *to) {
    for (size_t k = 0; k < n; k++) switch (kind) {
        case K_FLOAT64: ((double *)to)[k] = v[k].f; break;
        case K_INT32: ((int32_t *)to)[k] = v[k].i; break;
        case K_BOOLEAN: ((bool *)to)[k] = v[k].b; break;
        case K_STRING: ((const char **)to)[k] = v[k].s; break;
        case K_UINT64: ((uint64_t *)to)[k] = v[k].u; break;
        }
    return to;
}

static Value parse_value(Kind kind, const char *tok, int k) {
    Value v;
    memset(&v, 0, sizeof v);
    switch (kind) {
    case K_FLOAT64: v.f = real_arg(tok); break;
    case K_INT32: v.i = (int32_t)strtol(tok, NULL, 10); break;
    case K_BOOLEAN: v.b = atoi(tok) != 0; break;
    case K_STRING: v.s = str_arg(tok, k); break;
    case K_UINT64: v.u = strtoull(tok, NULL, 10); break;
    }
    return v;
}

/* Prints n values of `kind` from the array `from` of that C type. */
static void print_values(Kind kind, const void *from, size_t n, char *out, size_t out_size) {
    size_t used = 0;
    for (size_t k = 0; k < n && used + 24 < out_size; k++) switch (kind) {
        case K_FLOAT64: used += put_real(out + used, out_size - used, ((const double *)from)[k]); break;
        case K_INT32: used += snprintf(out + used, out_size - used, " %d", (int)((const int32_t *)from)[k]); break;
        case K_BOOLEAN: used += snprintf(out + used, out_size - used, " %d", ((const bool *)from)[k]); break;
        case K_STRING: used += put_string(out + used, out_size - used, ((const char *const *)from)[k]); break;
        case K_UINT64:
            used += snprintf(out + used, out_size - used, " %" PRIu64, ((const uint64_t *)from)[k]);
            break;
        }
}

/* The number of threads of this process. */
static int process_threads(void) {
    int n = 0;
#ifdef _WIN32
    HANDLE snap = CreateToolhelp32Snapshot(TH32CS_SNAPTHREAD, 0);
    THREADENTRY32 e;
    e.dwSize = sizeof e;
    if (snap == INVALID_HANDLE_VALUE) return -1;
    for (BOOL more = Thread32First(snap, &e); more; more = Thread32Next(snap, &e))
        n += e.th32OwnerProcessID == GetCurrentProcessId();
    CloseHandle(snap);
#else
    DIR *d = opendir("/proc/self/task");
    if (!d) return -1;
    for (struct dirent *e; (e = readdir(d));) n += e->d_name[0] != '.';
    closedir(d);
#endif
    return n;
}

/* This thread's x87 control word (the precision and rounding of the x87 unit). */
static unsigned x87_control_word(void) {
    unsigned short word;
    __asm__ volatile("fnstcw %0" : "=m"(word));
    return word;
}

/* The value references t[0..n-1]. */
static void read_vrs(char **t, int n, VR *vrs) {
    for (int k = 0; k < n; k++) vrs[k] = (VR)strtoul(t[k], NULL, 10);
}

/* A call with a null instance (the other arguments valid). */
static Status null_call(const char *function) {
    VR vr[1] = {0};
    double r[1] = {0};
    bool flags[4];
    if (!strcmp(function, "fmi3FreeInstance")) {
        FN(void (*)(Comp), function)(NULL);
        return 0;
    }
    if (!strcmp(function, "fmi3GetFloat64")) return FN(FArray, function)(NULL, vr, 1, r, 1);
    if (!strcmp(function, "fmi3DoStep"))
        return FN(Status(*)(Comp, double, double, bool, bool *, bool *, bool *, double *), function)(
            NULL, 0, 1e-3, true, &flags[0], &flags[1], &flags[2], r);
    if (!strcmp(function, "fmi3EnterInitializationMode"))
        return FN(Status(*)(Comp, bool, double, double, bool, double), function)(NULL, false, 0, 0, false, 0);
    if (!strcmp(function, "fmi3GetFMUState")) return FN(Status(*)(Comp, State *), function)(NULL, &states[0]);
    return FN(Status(*)(Comp), function)(NULL);
}

/* dirder and adjoint: NU U... NK K... NSEED SEED... NSENSITIVITY. */
static Status derivative(Comp c, const char *function, int n, char **t, char *out, size_t out_size) {
    VR unknowns[MAX_VALUES], knowns[MAX_VALUES];
    double seed[MAX_VALUES], sensitivity[MAX_VALUES];
    int nu = atoi(t[1]);
    if (nu < 0 || nu > MAX_VALUES || 3 + nu > n) return -1;
    int nk = atoi(t[2 + nu]);
    if (nk < 0 || nk > MAX_VALUES || 4 + nu + nk > n) return -1;
    int ns = atoi(t[3 + nu + nk]);
    if (ns < 0 || ns > MAX_VALUES || 5 + nu + nk + ns > n) return -1;
    int nsens = atoi(t[4 + nu + nk + ns]);
    if (nsens < 0 || nsens > MAX_VALUES) return -1;
    read_vrs(t + 2, nu, unknowns);
    read_vrs(t + 3 + nu, nk, knowns);
    for (int k = 0; k < ns; k++) seed[k] = real_arg(t[4 + nu + nk + k]);
    Status s = FN(Status(*)(Comp, const VR *, size_t, const VR *, size_t, const double *, size_t, double *,
                            size_t),
                  function)(c, unknowns, (size_t)nu, knowns, (size_t)nk, seed, (size_t)ns, sensitivity,
                            (size_t)nsens);
    if (s <= 1) print_values(K_FLOAT64, sensitivity, (size_t)nsens, out, out_size);
    return s;
}

static Status run_line(int slot, int n, char **t, char *out, size_t out_size) {
    Comp c = instances[slot];
    const char *cmd = t[0];
    VR vrs[MAX_VALUES];
    out[0] = 0;
    for (size_t k = 0; k < sizeof nullary / sizeof nullary[0]; k++)
        if (!strcmp(cmd, nullary[k].command)) return FN(Status(*)(Comp), nullary[k].function)(c);
    Status handled = run_state_command(&state_functions, c, cmd, t, out, out_size);
    if (handled != NOT_A_STATE_COMMAND) return handled;
    if (!strcmp(cmd, "null") && n == 2) return null_call(t[1]);
    if (!strcmp(cmd, "version")) {
        put_string(out, out_size, FN(const char *(*)(void), "fmi3GetVersion")());
        return 0;
    }
    if (!strcmp(cmd, "process_threads")) {
        snprintf(out, out_size, " %d", process_threads());
        return 0;
    }
    if (!strcmp(cmd, "x87_control_word")) {
        snprintf(out, out_size, " %04x", x87_control_word());
        return 0;
    }
    if (!strcmp(cmd, "instantiate_cs") && n == 6) {
        instances[slot] = FN(Comp(*)(const char *, const char *, const char *, bool, bool, bool, bool, const VR *,
                                     size_t, void *, Logger, void *),
                             "fmi3InstantiateCoSimulation")(str_arg(t[1], 1), str_arg(t[2], 2), str_arg(t[3], 3),
                                                            false, atoi(t[4]) != 0, atoi(t[5]) != 0, false,
                                                            NULL, 0, NULL, logger, NULL);
        return instances[slot] ? 0 : 3;
    }
    if (!strcmp(cmd, "instantiate_me") && n == 5) {
        instances[slot] =
            FN(Comp(*)(const char *, const char *, const char *, bool, bool, void *, Logger),
               "fmi3InstantiateModelExchange")(str_arg(t[1], 1), str_arg(t[2], 2), str_arg(t[3], 3), false,
                                               atoi(t[4]) != 0, NULL, logger);
        return instances[slot] ? 0 : 3;
    }
    if (!strcmp(cmd, "free")) {
        FN(void (*)(Comp), "fmi3FreeInstance")(c);
        instances[slot] = NULL;
        return 0;
    }
    if (!strcmp(cmd, "enter_init") && n == 2)
        return FN(Status(*)(Comp, bool, double, double, bool, double), "fmi3EnterInitializationMode")(
            c, false, 0, real_arg(t[1]), false, 0);
    if (!strncmp(cmd, "set_", 4) && kind_of(cmd, 4) >= 0 && n >= 2) {
        Kind kind = (Kind)kind_of(cmd, 4);
        static Value values[MAX_VALUES];
        static unsigned char array[MAX_VALUES * sizeof(Value)];
        int nvr = atoi(t[1]);
        if (nvr < 0 || nvr > MAX_VALUES || n < 3 + nvr) return -1;
        int nv = atoi(t[2 + nvr]);
        if (nv < 0 || nv > MAX_VALUES || n < 3 + nvr + nv) return -1;
        read_vrs(t + 2, nvr, vrs);
        for (int k = 0; k < nv; k++) values[k] = parse_value(kind, t[3 + nvr + k], 3 + nvr + k);
        return FN(FArray, kinds[kind].set)(c, vrs, (size_t)nvr, packed(kind, values, (size_t)nv, array),
                                           (size_t)nv);
    }
    if (!strncmp(cmd, "get_", 4) && kind_of(cmd, 4) >= 0 && n >= 2) {
        Kind kind = (Kind)kind_of(cmd, 4);
        static unsigned char array[MAX_VALUES * sizeof(Value)];
        int nv = atoi(t[1]), nvr = n - 2;
        if (nv < 0 || nv > MAX_VALUES || nvr > MAX_VALUES) return -1;
        read_vrs(t + 2, nvr, vrs);
        memset(array, 0, sizeof array);
        Status s = FN(FArray, kinds[kind].get)(c, vrs, (size_t)nvr, array, (size_t)nv);
        if (s <= 1) print_values(kind, array, (size_t)nv, out, out_size);
        return s;
    }
    if (!strcmp(cmd, "do_step") && n == 3) {
        bool flags[3];
        double last = -1;
        memset(flags, 0xff, sizeof flags);
        Status s = FN(Status(*)(Comp, double, double, bool, bool *, bool *, bool *, double *), "fmi3DoStep")(
            c, real_arg(t[1]), real_arg(t[2]), true, &flags[0], &flags[1], &flags[2], &last);
        print_values(K_BOOLEAN, flags, 3, out, out_size);
        put_real(out + strlen(out), out_size - strlen(out), last);
        return s;
    }
    if (!strcmp(cmd, "set_time") && n == 2) return FN(Status(*)(Comp, double), "fmi3SetTime")(c, real_arg(t[1]));
    if (!strcmp(cmd, "completed")) {
        bool flags[2];
        memset(flags, 0xff, sizeof flags);
        Status s = FN(Status(*)(Comp, bool, bool *, bool *), "fmi3CompletedIntegratorStep")(c, true, &flags[0],
                                                                                           &flags[1]);
        print_values(K_BOOLEAN, flags, 2, out, out_size);
        return s;
    }
    if (!strcmp(cmd, "update_discrete")) {
        bool flags[5];
        double next = -1;
        memset(flags, 0xff, sizeof flags);
        Status s = FN(Status(*)(Comp, bool *, bool *, bool *, bool *, bool *, double *),
                      "fmi3UpdateDiscreteStates")(c, &flags[0], &flags[1], &flags[2], &flags[3], &flags[4], &next);
        print_values(K_BOOLEAN, flags, 5, out, out_size);
        put_real(out + strlen(out), out_size - strlen(out), next);
        return s;
    }
    if (!strcmp(cmd, "dirder") || !strcmp(cmd, "adjoint"))
        return derivative(c, !strcmp(cmd, "dirder") ? "fmi3GetDirectionalDerivative" : "fmi3GetAdjointDerivative",
                          n, t, out, out_size);
    return -1; /* an unknown command: a broken plan */
}

int main(int argc, char **argv) { return run_plan(argc, argv, run_line); }
