/* A shared library that is no SyROF app: it exports no syrof_app_entry. */
int not_an_app(void) { return 7; }
