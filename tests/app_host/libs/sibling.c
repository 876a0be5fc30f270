/* A shared library of the student's own beside the app library (libs/),
 * which needs_sibling links: the host's Landlock rules name each shared
 * object beside the app, so the loader reads and maps it. */
int SiblingAnswer(void) { return 42; }
