/* An FMI 2.0 master that runs a plan of calls against an FMU's shared library, as an importer would: the
 * library loaded with LoadLibrary (Windows) or dlopen (elsewhere), the functions found by name, a variadic
 * logger that formats its message as printf does.
 *
 * The same source is built for Linux (gcc) and for Windows (MinGW-w64, run under Wine), so that the two
 * binaries of the FMU run the same calls and tests/win64/test_win64.py compares what they return.
 *
 * Usage: harness LIBRARY PLAN
 *
 * PLAN has one call per line, `<instance slot 0-3> <command> <arguments>`; strings are hex-encoded UTF-8
 * bytes ("-" is a null pointer, "." the empty string), Reals the 16 hex digits of their IEEE 754 bits (so
 * NaN, infinities and every last bit pass through unchanged). For each line the harness prints the lines
 * the FMU logged during the call (`L <status> <category hex> <message hex>`), then `R <line> <status>` and
 * the values the call returned (Reals as bits, strings hex); status 8 means a file the plan names could not
 * be read or written. What it shares with the FMI 3.0 master harness3.c is in plan.h. Commands (see
 * `run_line`):
 *   instantiate NAME TYPE GUID URI LOGGING   free   setup START   enter_init   exit_init   terminate   reset
 *   set_real VR BITS...   set_integer VR I...   set_boolean VR B...   set_string VR S...
 *   get_real VR...   get_integer VR...   get_boolean VR...   get_string VR...
 *   do_step T H   cancel_step   set_time T   enter_event   enter_ct   completed   new_discrete
 *   get_derivatives N   get_event_indicators N   get_continuous_states N   get_nominals N   set_continuous_states N
 *   dirder NU U... NK K... SEED...   get_status KIND   get_real_status KIND   debug_logging ON CAT...
 *   get_state S   set_state S   free_state S   serialize S FILE   deserialize S FILE   flip FILE OFFSET
 *   null FUNCTION (the function called with a null component)   versions
 * A crash ends the process: the last `R` line tells which call it was.
 */
#include <stdarg.h>

#include "plan.h"

typedef unsigned int VR;
typedef void (*Logger)(void *, const char *, int, const char *, const char *, ...);
typedef struct {
    Logger logger;
    void *(*allocate)(size_t, size_t);
    void (*free)(void *);
    void (*step_finished)(void *, int);
    void *env;
} Callbacks;
typedef struct {
    int new_discrete_states_needed, terminate_simulation, nominals_changed, values_changed,
        next_event_time_defined;
    double next_event_time;
} EventInfo;

/* The logger: the message is a printf format with the variadic arguments. */
static void logger(void *env, const char *name, int status, const char *category, const char *fmt, ...) {
    char buf[16384];
    va_list ap;
    (void)env;
    (void)name;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt ? fmt : "(null)", ap);
    va_end(ap);
    log_line(status, category, buf);
}

static Callbacks callbacks = {logger, calloc, free, NULL, NULL};

typedef Status (*F0)(Comp);
typedef Status (*FGetR)(Comp, const VR *, size_t, double *);
typedef Status (*FGetI)(Comp, const VR *, size_t, int *);
typedef Status (*FGetS)(Comp, const VR *, size_t, const char **);
typedef Status (*FSetR)(Comp, const VR *, size_t, const double *);
typedef Status (*FSetI)(Comp, const VR *, size_t, const int *);
typedef Status (*FSetS)(Comp, const VR *, size_t, const char *const *);
typedef Status (*FArr)(Comp, double *, size_t);

/* The zero-argument (component only) functions, by command. */
static const struct {
    const char *command, *function;
} nullary[] = {
    {"enter_init", "fmi2EnterInitializationMode"}, {"exit_init", "fmi2ExitInitializationMode"},
    {"terminate", "fmi2Terminate"}, {"reset", "fmi2Reset"}, {"cancel_step", "fmi2CancelStep"},
    {"enter_event", "fmi2EnterEventMode"}, {"enter_ct", "fmi2EnterContinuousTimeMode"},
};

static const StateFunctions state_functions = {
    "fmi2GetFMUstate",           "fmi2SetFMUstate",       "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
};

/* Runs one plan line (its tokens after the slot); returns the status, printing returned values. */
static Status run_line(int slot, int n, char **t, char *out, size_t out_size) {
    Comp c = instances[slot];
    const char *cmd = t[0];
    int nv = n - 1;
    VR vrs[MAX_VALUES];
    if (nv > MAX_VALUES) nv = MAX_VALUES;
    out[0] = 0;
    for (size_t k = 0; k < sizeof nullary / sizeof nullary[0]; k++)
        if (!strcmp(cmd, nullary[k].command)) return FN(F0, nullary[k].function)(c);
    if (!strcmp(cmd, "null")) {
        /* t[1]: a function taking the component first; null component, other arguments harmless */
        double r[1] = {0};
        if (!strcmp(t[1], "fmi2FreeInstance")) {
            FN(void (*)(Comp), "fmi2FreeInstance")(NULL);
            return 0;
        }
        if (!strcmp(t[1], "fmi2GetReal")) return FN(FGetR, "fmi2GetReal")(NULL, vrs, 0, r);
        if (!strcmp(t[1], "fmi2DoStep"))
            return FN(Status(*)(Comp, double, double, int), "fmi2DoStep")(NULL, 0, 1e-3, 1);
        return FN(F0, t[1])(NULL);
    }
    if (!strcmp(cmd, "versions")) {
        snprintf(out, out_size, " %s %s", FN(const char *(*)(void), "fmi2GetTypesPlatform")(),
                 FN(const char *(*)(void), "fmi2GetVersion")());
        return 0;
    }
    Status handled = run_state_command(&state_functions, c, cmd, t, out, out_size);
    if (handled != NOT_A_STATE_COMMAND) return handled;
    if (!strcmp(cmd, "instantiate")) {
        Comp made = FN(Comp(*)(const char *, int, const char *, const char *, const Callbacks *, int, int),
                       "fmi2Instantiate")(str_arg(t[1], 1), atoi(t[2]), str_arg(t[3], 3), str_arg(t[4], 4),
                                          &callbacks, 0, atoi(t[5]));
        instances[slot] = made;
        return made ? 0 : 3;
    }
    if (!strcmp(cmd, "free")) {
        FN(void (*)(Comp), "fmi2FreeInstance")(c);
        instances[slot] = NULL;
        return 0;
    }
    if (!strcmp(cmd, "setup"))
        return FN(Status(*)(Comp, int, double, double, int, double), "fmi2SetupExperiment")(
            c, 0, 0, real_arg(t[1]), 0, 0);
    if (!strncmp(cmd, "set_", 4) && strcmp(cmd, "set_time") && strcmp(cmd, "set_state") &&
        strcmp(cmd, "set_continuous_states")) {
        int m = nv / 2;
        double r[MAX_VALUES];
        int iv[MAX_VALUES];
        const char *sv[MAX_VALUES];
        for (int k = 0; k < m; k++) {
            vrs[k] = (VR)strtoul(t[1 + 2 * k], NULL, 10);
            r[k] = real_arg(t[2 + 2 * k]);
            iv[k] = atoi(t[2 + 2 * k]);
            sv[k] = str_arg(t[2 + 2 * k], 2 + 2 * k);
        }
        if (!strcmp(cmd, "set_real")) return FN(FSetR, "fmi2SetReal")(c, vrs, m, r);
        if (!strcmp(cmd, "set_integer")) return FN(FSetI, "fmi2SetInteger")(c, vrs, m, iv);
        if (!strcmp(cmd, "set_boolean")) return FN(FSetI, "fmi2SetBoolean")(c, vrs, m, iv);
        if (!strcmp(cmd, "set_string")) return FN(FSetS, "fmi2SetString")(c, vrs, m, sv);
    }
    if (!strcmp(cmd, "get_real") || !strcmp(cmd, "get_integer") || !strcmp(cmd, "get_boolean") ||
        !strcmp(cmd, "get_string")) {
        double r[MAX_VALUES];
        int iv[MAX_VALUES];
        const char *sv[MAX_VALUES] = {0};
        Status s;
        size_t used = 0;
        for (int k = 0; k < nv; k++) vrs[k] = (VR)strtoul(t[1 + k], NULL, 10);
        if (!strcmp(cmd, "get_real")) {
            s = FN(FGetR, "fmi2GetReal")(c, vrs, nv, r);
            if (s <= 1)
                for (int k = 0; k < nv; k++) used += put_real(out + used, out_size - used, r[k]);
        } else if (!strcmp(cmd, "get_string")) {
            s = FN(FGetS, "fmi2GetString")(c, vrs, nv, sv);
            if (s <= 1)
                for (int k = 0; k < nv; k++) used += put_string(out + used, out_size - used, sv[k]);
        } else {
            s = FN(FGetI, !strcmp(cmd, "get_integer") ? "fmi2GetInteger" : "fmi2GetBoolean")(c, vrs, nv, iv);
            if (s <= 1)
                for (int k = 0; k < nv; k++) used += snprintf(out + used, out_size - used, " %d", iv[k]);
        }
        return s;
    }
    if (!strcmp(cmd, "do_step"))
        return FN(Status(*)(Comp, double, double, int), "fmi2DoStep")(c, real_arg(t[1]), real_arg(t[2]), 1);
    if (!strcmp(cmd, "set_time")) return FN(Status(*)(Comp, double), "fmi2SetTime")(c, real_arg(t[1]));
    if (!strcmp(cmd, "completed")) {
        int event = -1, stop = -1;
        Status s = FN(Status(*)(Comp, int, int *, int *), "fmi2CompletedIntegratorStep")(c, 1, &event, &stop);
        snprintf(out, out_size, " %d %d", event, stop);
        return s;
    }
    if (!strcmp(cmd, "new_discrete")) {
        EventInfo e;
        memset(&e, 0xff, sizeof e);
        Status s = FN(Status(*)(Comp, EventInfo *), "fmi2NewDiscreteStates")(c, &e);
        snprintf(out, out_size, " %d %d %d %d %d", e.new_discrete_states_needed, e.terminate_simulation,
                 e.nominals_changed, e.values_changed, e.next_event_time_defined);
        return s;
    }
    if (!strcmp(cmd, "get_derivatives") || !strcmp(cmd, "get_event_indicators") ||
        !strcmp(cmd, "get_continuous_states") || !strcmp(cmd, "get_nominals") ||
        !strcmp(cmd, "set_continuous_states")) {
        static const char *functions[][2] = {
            {"get_derivatives", "fmi2GetDerivatives"},
            {"get_event_indicators", "fmi2GetEventIndicators"},
            {"get_continuous_states", "fmi2GetContinuousStates"},
            {"get_nominals", "fmi2GetNominalsOfContinuousStates"},
            {"set_continuous_states", "fmi2SetContinuousStates"},
        };
        double r[MAX_VALUES] = {0};
        size_t m = (size_t)atoi(t[1]);
        for (size_t k = 0; k < 5; k++)
            if (!strcmp(cmd, functions[k][0])) return FN(FArr, functions[k][1])(c, m ? r : NULL, m);
    }
    if (!strcmp(cmd, "dirder")) {
        VR known[MAX_VALUES];
        double seed[MAX_VALUES], dv[MAX_VALUES];
        int nu = atoi(t[1]), nk = atoi(t[2 + nu]);
        if (nu > MAX_VALUES || nk > MAX_VALUES || 3 + nu + 2 * nk > n) return -1;
        for (int k = 0; k < nu; k++) vrs[k] = (VR)strtoul(t[2 + k], NULL, 10);
        for (int k = 0; k < nk; k++) known[k] = (VR)strtoul(t[3 + nu + k], NULL, 10);
        for (int k = 0; k < nk; k++) seed[k] = real_arg(t[3 + nu + nk + k]);
        Status s = FN(Status(*)(Comp, const VR *, size_t, const VR *, size_t, const double *, double *),
                      "fmi2GetDirectionalDerivative")(c, vrs, nu, known, nk, seed, dv);
        size_t used = 0;
        if (s <= 1)
            for (int k = 0; k < nu; k++) used += put_real(out + used, out_size - used, dv[k]);
        return s;
    }
    if (!strcmp(cmd, "get_status") || !strcmp(cmd, "get_real_status")) {
        if (!strcmp(cmd, "get_status")) {
            int v = -1;
            Status s = FN(Status(*)(Comp, int, int *), "fmi2GetStatus")(c, atoi(t[1]), &v);
            snprintf(out, out_size, " %d", v);
            return s;
        }
        double v = -1;
        Status s = FN(Status(*)(Comp, int, double *), "fmi2GetRealStatus")(c, atoi(t[1]), &v);
        put_real(out, out_size, v);
        return s;
    }
    if (!strcmp(cmd, "debug_logging")) {
        const char *cats[MAX_VALUES];
        for (int k = 0; k + 2 < n && k < MAX_VALUES; k++) cats[k] = str_arg(t[2 + k], 2 + k);
        return FN(Status(*)(Comp, int, size_t, const char *const *), "fmi2SetDebugLogging")(
            c, atoi(t[1]), n > 2 ? (size_t)(n - 2) : 0, cats);
    }
    return -1; /* an unknown command: a broken plan */
}

int main(int argc, char **argv) { return run_plan(argc, argv, run_line); }
