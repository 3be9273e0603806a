/* jsonq: reads JSON reports for the integration tests, so they check parsed values instead of
 * matching substrings of flattened text.
 *
 *   jsonq get FILE PATH...          prints each value, one per line (numbers as %.17g, strings
 *                                   bare, objects and arrays as compact JSON); exit 2 naming the
 *                                   first PATH that is not there
 *   jsonq has FILE PATH...          exit 0 when every PATH is there, else 1 naming the missing ones
 *   jsonq same A B TOL PATH...      the values at each PATH agree in A and B: numbers to a relative
 *                                   TOL (|a - b| <= TOL max(|a|, |b|)), anything else exactly; exit 1
 *                                   listing every difference
 *
 * PATH: keys separated by dots, array elements by [i], e.g. methods[2].cubature.elements. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static cJSON *load(const char *file)
{
    FILE *f = fopen(file, "rb");
    if (!f) {
        fprintf(stderr, "jsonq: cannot open %s\n", file);
        exit(2);
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 1);
    if (!text || fread(text, 1, (size_t)n, f) != (size_t)n) {
        fprintf(stderr, "jsonq: cannot read %s\n", file);
        exit(2);
    }
    text[n] = 0;
    fclose(f);
    cJSON *j = cJSON_Parse(text);
    free(text);
    if (!j) {
        fprintf(stderr, "jsonq: %s is not JSON\n", file);
        exit(2);
    }
    return j;
}

/* The value at path under root, or NULL. */
static const cJSON *find(const cJSON *root, const char *path)
{
    const cJSON *at = root;
    const char *p = path;
    while (*p && at) {
        if (*p == '.') p++;
        if (*p == '[') {
            char *end;
            long i = strtol(p + 1, &end, 10);
            if (*end != ']' || !cJSON_IsArray(at)) return NULL;
            at = cJSON_GetArrayItem(at, (int)i);
            p = end + 1;
            continue;
        }
        size_t len = strcspn(p, ".[");
        char key[256];
        if (len == 0 || len >= sizeof key || !cJSON_IsObject(at)) return NULL;
        memcpy(key, p, len);
        key[len] = 0;
        at = cJSON_GetObjectItemCaseSensitive(at, key);
        p += len;
    }
    return at;
}

static void print_value(const cJSON *v)
{
    if (cJSON_IsNumber(v)) {
        printf("%.17g\n", v->valuedouble);
    } else if (cJSON_IsString(v)) {
        printf("%s\n", v->valuestring);
    } else {
        char *s = cJSON_PrintUnformatted(v);
        printf("%s\n", s ? s : "?");
        free(s);
    }
}

static int same(const cJSON *a, const cJSON *b, double tol)
{
    if (cJSON_IsNumber(a) && cJSON_IsNumber(b)) {
        double x = a->valuedouble, y = b->valuedouble;
        return fabs(x - y) <= tol * fmax(fabs(x), fabs(y));
    }
    return cJSON_Compare(a, b, 1);
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: jsonq get|has FILE PATH... | jsonq same A B TOL PATH...\n");
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "get") || !strcmp(cmd, "has")) {
        cJSON *j = load(argv[2]);
        int missing = 0;
        for (int i = 3; i < argc; i++) {
            const cJSON *v = find(j, argv[i]);
            if (!v) {
                fprintf(stderr, "jsonq: %s has no %s\n", argv[2], argv[i]);
                missing++;
                if (!strcmp(cmd, "get")) return 2;
            } else if (!strcmp(cmd, "get")) {
                print_value(v);
            }
        }
        cJSON_Delete(j);
        return missing ? 1 : 0;
    }
    if (!strcmp(cmd, "same") && argc >= 6) {
        cJSON *a = load(argv[2]), *b = load(argv[3]);
        double tol = atof(argv[4]);
        int differ = 0;
        for (int i = 5; i < argc; i++) {
            const cJSON *va = find(a, argv[i]), *vb = find(b, argv[i]);
            if (!va || !vb) {
                printf("%s: %s\n", argv[i], !va ? "missing in the first" : "missing in the second");
                differ++;
            } else if (!same(va, vb, tol)) {
                char *sa = cJSON_PrintUnformatted(va), *sb = cJSON_PrintUnformatted(vb);
                printf("%s: %s vs %s\n", argv[i], sa, sb);
                free(sa), free(sb);
                differ++;
            }
        }
        cJSON_Delete(a), cJSON_Delete(b);
        return differ ? 1 : 0;
    }
    fprintf(stderr, "jsonq: unknown command %s\n", cmd);
    return 2;
}
